// Map archives: an MRPT archive holding a serialised pndt::PanopticNDTMap, read by
// loadMapArchive() (gzip or plain: zlib passes plain bytes through, so the seeds are
// uncompressed archives and the fuzzer mutates the serialised map, not deflate data).
#include <pndt/mrpt/map_files.h>

#include "fuzz_util.h"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string path = pndt_fuzz::writeInput(data, size, ".pndt");
    try
    {
        const auto map = pndt::loadMapArchive(path);
        const auto& core = map->core();
        core.finalize();
        (void)core.voxels().size();
    }
    catch (const std::exception&)
    {
    }
    return 0;
}
