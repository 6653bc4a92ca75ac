// Every text pose format. First byte selects: tum, rtabmap0/1/2/4/10/11, kitti, redwood.
#include <pndt/io/poses.h>

#include "fuzz_util.h"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using pndt::io::PoseFormat;
    static constexpr PoseFormat kFormats[] = {PoseFormat::Tum,      PoseFormat::Rtabmap0,  PoseFormat::Rtabmap1,
                                              PoseFormat::Rtabmap2, PoseFormat::Rtabmap4,  PoseFormat::Rtabmap10,
                                              PoseFormat::Rtabmap11, PoseFormat::Kitti,    PoseFormat::Redwood};
    const uint8_t sel = pndt_fuzz::takeSelector(data, size);
    const PoseFormat format = kFormats[sel % (sizeof(kFormats) / sizeof(kFormats[0]))];
    const std::string path = pndt_fuzz::writeInput(data, size, ".txt");
    pndt::io::PoseReadOptions options;
    options.non_finite_is_error = (sel & 0x80) != 0;
    pndt::io::PoseReadReport report;
    try
    {
        (void)pndt::io::readPoseFile(path, format, options, &report);
    }
    catch (const std::exception&)
    {
    }
    return 0;
}
