// Map archives: an MRPT archive holding a serialised pndt::PanopticNDTMap, read by
// loadMapArchive() (gzip or plain: zlib passes plain bytes through, so the seeds are
// uncompressed archives and the fuzzer mutates the serialised map, not deflate data).
// A map of format version 6 ends with the CRC-32 of its payload: the input's CRC is
// set to match its (mutated) payload first, or nearly every input would stop at the
// checksum and the readers behind it would go unfuzzed.
#include <pndt/mrpt/map_files.h>
#include <zlib.h>

#include "fuzz_util.h"

#include <cstring>
#include <exception>
#include <string_view>
#include <vector>

namespace
{
/// MRPT's framing of one object: [0x80 | name length][name][version] payload [0x88];
/// version 6's payload ends with its CRC-32 (u32, little-endian).
void matchChecksum(std::vector<uint8_t>& in)
{
    constexpr std::string_view kName = "pndt::PanopticNDTMap";
    const size_t head = 2 + kName.size();
    if (in.size() < head + 5 || in[0] != (0x80 | kName.size()) || in[head - 1] != 6) return;
    if (std::string_view(reinterpret_cast<const char*>(in.data() + 1), kName.size()) != kName) return;
    const size_t crc_at = in.size() - 5;
    const uint32_t crc = uint32_t(crc32(crc32(0L, Z_NULL, 0), in.data() + head, uInt(crc_at - head)));
    std::memcpy(in.data() + crc_at, &crc, 4);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    std::vector<uint8_t> input(data, data + size);
    matchChecksum(input);
    const std::string path = pndt_fuzz::writeInput(input.data(), input.size(), ".pndt");
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
