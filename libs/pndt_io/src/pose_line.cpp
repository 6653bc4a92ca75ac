#include <pndt/io/pose_line.h>

#include "pose_math.h"
#include "text_util.h"

#include <fmt/format.h>

namespace pndt::io
{
using namespace detail;
}
namespace pndt::io
{
std::optional<StampedPose> parseStampedPoseLine(const std::string& line, bool with_id, const std::string& where)
{
    if (isBlankOrComment(line)) return std::nullopt;
    const auto tok = splitWs(line);
    const size_t expected = with_id ? 9 : 8;
    const char* layout = with_id ? "stamp x y z qx qy qz qw id" : "stamp x y z qx qy qz qw";
    if (tok.size() != expected)
        throw InputError(fmt::format("{}: expected {} values ({}), got {}", where, expected, layout, tok.size()));
    double v[8];
    for (size_t i = 0; i < 8; ++i)
        if (!parseDouble(tok[i], v[i]))
            throw InputError(fmt::format("{}: value {} '{}' is not a number", where, i + 1, tok[i]));
    StampedPose sp;
    if (with_id && !parseInt64(tok[8], sp.id))
        throw InputError(fmt::format("{}: id '{}' is not an integer", where, tok[8]));
    if (!allFinite(v, 8)) throw InputError(fmt::format("{}: pose contains non-finite values", where));
    sp.t = v[0];
    const std::string err = detail::poseFromTranslationQuaternion(v + 1, v + 4, sp.T_world_sensor);
    if (!err.empty()) throw InputError(fmt::format("{}: {}", where, err));
    return sp;
}
}  // namespace pndt::io
