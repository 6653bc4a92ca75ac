// Redwood / Open3D trajectory `.log`: per frame a header line `id id n` (id = the frame: block i
// has id i) and 4 matrix rows (camera-to-world, optical axes).
#include "redwood_log.h"

#include "pose_math.h"
#include "pose_text.h"
#include "text_util.h"

#include <fmt/format.h>

#include <cmath>

namespace pndt::io
{
namespace detail
{
std::vector<RedwoodBlock> readRedwoodLogBlocks(const std::string& path, double frame_rate_hz)
{
    if (!(frame_rate_hz > 0) || !std::isfinite(frame_rate_hz))
        throw InputError(fmt::format("{}: frame_rate_hz must be > 0 (got {})", path,
                                     frame_rate_hz));
    detail::LineReader in(path);
    std::vector<RedwoodBlock> blocks;
    std::string line;
    int64_t block = 0;

    auto nextDataLine = [&](std::vector<std::string_view>& tok) -> bool {
        while (in.next(line))
        {
            if (detail::isBlankOrComment(line)) continue;
            tok = detail::splitWs(line);
            return true;
        }
        return false;
    };

    std::vector<std::string_view> tok;
    while (nextDataLine(tok))
    {
        const size_t header_line = in.lineNo();
        if (tok.size() != 3)
            failLine(path, header_line,
                     fmt::format("expected a block header of 3 integers (id id n), got {} values",
                                 tok.size()));
        StampedPose sp;
        if (!detail::parseInt64(tok[0], sp.id))
            failLine(path, header_line,
                     fmt::format("block header value '{}' is not an integer", tok[0]));
        // Frame i is block i (Open3D writes `i i i+1`): a block whose id is not its place in the
        // file means a frame missing or out of order, which would shift every later pose.
        if (sp.id != block)
            failLine(path, header_line,
                     fmt::format("block {} of the file has frame id {} (header '{} {} {}'): a frame missing or out "
                                 "of order? Frame i must be the i-th block",
                                 block, sp.id, tok[0], tok[1], tok[2]));
        double m[16];
        size_t first_row_line = 0;
        for (int r = 0; r < 4; ++r)
        {
            if (!nextDataLine(tok))
                failLine(path, in.lineNo() + 1,
                         fmt::format("file ends inside the block starting at line {} (matrix row "
                                     "{} of 4 missing)",
                                     header_line, r + 1));
            if (tok.size() != 4)
                failLine(path, in.lineNo(),
                         fmt::format("expected 4 values in matrix row {} of the block starting at "
                                     "line {}, got {}",
                                     r + 1, header_line, tok.size()));
            detail::parseDoubles(tok, 0, 4, m + 4 * r, path, in.lineNo());
            if (r == 0) first_row_line = in.lineNo();
        }
        const int64_t my_block = block++;
        sp.t = static_cast<double>(my_block) / frame_rate_hz;
        RedwoodBlock blk;
        blk.where = fmt::format("{} (line {})", path, header_line);
        if (!detail::allFinite(m, 16))
        {
            blocks.push_back(std::move(blk));  // non-finite: no pose
            continue;
        }
        if (std::abs(m[12]) > 1e-6 || std::abs(m[13]) > 1e-6 || std::abs(m[14]) > 1e-6 ||
            std::abs(m[15] - 1.0) > 1e-6)
            failLine(path, in.lineNo(),
                     fmt::format("last matrix row must be 0 0 0 1, got {} {} {} {}", m[12], m[13],
                                 m[14], m[15]));
        const double r[9] = {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]};
        const double t[3] = {m[3], m[7], m[11]};
        const std::string err = detail::poseFromRotationTranslation(r, t, sp.T_world_sensor);
        if (!err.empty()) failLine(path, first_row_line, err);
        blk.pose = sp;
        blocks.push_back(std::move(blk));
    }
    return blocks;
}

}  // namespace detail

std::vector<StampedPose> readRedwoodLog(const std::string& path, const PoseReadOptions& options,
                                        PoseReadReport* report)
{
    std::vector<StampedPose> poses;
    for (auto& b : detail::readRedwoodLogBlocks(path, options.frame_rate_hz))
    {
        if (b.pose)
            poses.push_back(*b.pose);
        else
            detail::handleNonFinite(b.where, options, report);
    }
    return poses;
}

}  // namespace pndt::io
