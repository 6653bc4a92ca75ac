// One pose line of a stream (a TCP/UDP pose stream, a pose file being appended to), parsed
// with the same rules as the file readers in poses.h.
#pragma once

#include <pndt/io/poses.h>

#include <optional>
#include <string>

namespace pndt::io
{
/// `stamp x y z qx qy qz qw` (TUM, RTAB-Map 1/10) or, with `with_id`, the same plus an integer
/// node id (RTAB-Map 11). Blank and '#' lines give nullopt. Anything else that is not such a
/// line (wrong count, not a number, non-finite values, bad quaternion) throws InputError
/// "<where>: <problem>".
std::optional<StampedPose> parseStampedPoseLine(const std::string& line, bool with_id, const std::string& where);
}  // namespace pndt::io
