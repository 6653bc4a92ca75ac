// PoseFormat names and the readPoseFile() dispatcher.
#include "text_util.h"

#include <pndt/io/poses.h>

#include <fmt/format.h>

#include <utility>

namespace pndt::io
{
namespace
{
const std::pair<const char*, PoseFormat> kNames[] = {
    {"tum", PoseFormat::Tum},
    {"rtabmap0", PoseFormat::Rtabmap0},
    {"rtabmap1", PoseFormat::Rtabmap1},
    {"rtabmap2", PoseFormat::Rtabmap2},
    {"rtabmap4", PoseFormat::Rtabmap4},
    {"rtabmap10", PoseFormat::Rtabmap10},
    {"rtabmap11", PoseFormat::Rtabmap11},
    {"kitti", PoseFormat::Kitti},
    {"redwood", PoseFormat::Redwood},
    {"nicr", PoseFormat::Nicr},
    // aliases
    {"raw", PoseFormat::Rtabmap0},
    {"g2o", PoseFormat::Rtabmap4},
    {"log", PoseFormat::Redwood},
};
}  // namespace

PoseFormat parsePoseFormat(const std::string& name)
{
    const std::string key = detail::toLower(name);
    for (const auto& [n, f] : kNames)
        if (key == n) return f;
    std::string accepted;
    for (const auto& [n, f] : kNames)
    {
        (void)f;
        if (!accepted.empty()) accepted += ", ";
        accepted += n;
    }
    throw InputError(
        fmt::format("unknown pose format '{}' (accepted: {})", name, accepted));
}

std::string toString(PoseFormat format)
{
    for (const auto& [n, f] : kNames)
        if (f == format) return n;
    return "unknown";
}

bool isStampless(PoseFormat f)
{
    using F = PoseFormat;
    return f == F::Rtabmap0 || f == F::Rtabmap2 || f == F::Rtabmap4 || f == F::Kitti || f == F::Redwood;
}

std::vector<StampedPose> readPoseFile(const std::string& path, PoseFormat format,
                                      const PoseReadOptions& options, PoseReadReport* report)
{
    switch (format)
    {
        case PoseFormat::Tum: return readTumPoses(path, options, report);
        case PoseFormat::Rtabmap0: return readRtabmapPoses(path, 0, options, report);
        case PoseFormat::Rtabmap1: return readRtabmapPoses(path, 1, options, report);
        case PoseFormat::Rtabmap2: return readRtabmapPoses(path, 2, options, report);
        case PoseFormat::Rtabmap4: return readRtabmapPoses(path, 4, options, report);
        case PoseFormat::Rtabmap10: return readRtabmapPoses(path, 10, options, report);
        case PoseFormat::Rtabmap11: return readRtabmapPoses(path, 11, options, report);
        case PoseFormat::Kitti: return readKittiPoses(path, options, report);
        case PoseFormat::Redwood: return readRedwoodLog(path, options, report);
        case PoseFormat::Nicr: return readNicrPoses(path, options, report);
    }
    throw InputError(fmt::format("{}: invalid PoseFormat value {}", path, static_cast<int>(format)));
}

}  // namespace pndt::io
