#include <pndt/io/atomic_file.h>
#include <pndt/oni_virtual/virtual_scene.h>
#include <pndt/sim/renderer.h>
#include <pndt/sim/scene_builder.h>
#include <pndt/sim/trajectory.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pndt::oni_virtual
{
namespace
{
std::string trim(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return {};
    return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}
}  // namespace

VirtualCameraConfig VirtualCameraConfig::fromEnvironment()
{
    if (const char* p = std::getenv("PNDT_VIRTUAL_CAMERA"); p && *p) return fromFile(p);
    return {};
}

VirtualCameraConfig VirtualCameraConfig::fromFile(const std::string& path)
{
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open the virtual camera configuration");
    VirtualCameraConfig c;
    std::string line;
    int n = 0;
    while (std::getline(in, line))
    {
        ++n;
        line = trim(line.substr(0, line.find('#')));
        if (line.empty()) continue;
        const auto eq = line.find('=');
        const std::string where = path + " (line " + std::to_string(n) + ")";
        if (eq == std::string::npos) throw std::runtime_error(where + ": expected key = value");
        const std::string key = trim(line.substr(0, eq)), value = trim(line.substr(eq + 1));
        std::istringstream v(value);
        bool ok = true;
        if (key == "width") ok = bool(v >> c.width);
        else if (key == "height") ok = bool(v >> c.height);
        else if (key == "fps") ok = bool(v >> c.fps);
        else if (key == "loop_frames") ok = bool(v >> c.loop_frames);
        else if (key == "seed") ok = bool(v >> c.seed);
        else if (key == "radius") ok = bool(v >> c.radius);
        else if (key == "eye_height") ok = bool(v >> c.eye_height);
        else if (key == "unplug_after") ok = bool(v >> c.unplug_after);
        else if (key == "freeze_after") ok = bool(v >> c.freeze_after);
        else if (key == "clock_reset_after") ok = bool(v >> c.clock_reset_after);
        else if (key == "stamp_back_frame") ok = bool(v >> c.stamp_back_frame);
        else if (key == "clock_jump_after") ok = bool(v >> c.clock_jump_after);
        else if (key == "clock_jump_frames") ok = bool(v >> c.clock_jump_frames);
        else if (key == "serial") c.serial = value;
        else if (key == "uri") c.uri = value;
        else if (key == "pose_seconds") ok = bool(v >> c.pose_seconds);
        else if (key == "clock_file") c.clock_file = value;
        else throw std::runtime_error(where + ": unknown key '" + key + "'");
        if (!ok) throw std::runtime_error(where + ": bad value '" + value + "' for " + key);
    }
    if (c.width <= 0 || c.height <= 0 || c.fps <= 0 || c.loop_frames <= 0)
        throw std::runtime_error(path + ": width, height, fps and loop_frames must be positive");
    return c;
}

CameraIntrinsics VirtualCameraConfig::intrinsics() const
{
    const double s = width / 640.0;
    return CameraIntrinsics{width, height, 525.0 * s, 525.0 * s, (width - 1) / 2.0, (height - 1) / 2.0};
}

Pose cameraPoseAt(const VirtualCameraConfig& c, int64_t k)
{
    const double start = double(c.seed % 360) * sim::kTwoPi / 360.0;
    const int64_t i = k % c.loop_frames;
    const double a = start + double(i) * sim::kTwoPi / double(c.loop_frames);
    const Eigen::Vector3d eye(c.radius * std::cos(a), c.radius * std::sin(a), c.eye_height);
    return sim::lookAt(eye, Eigen::Vector3d(0, 0, 0.45));
}

void writeTrajectoryTum(const VirtualCameraConfig& c, const std::string& path)
{
    std::ostringstream out;
    out << "# pndt virtual camera: optical camera poses, TUM format (t tx ty tz qx qy qz qw)\n";
    const int64_t n = int64_t(std::llround(c.pose_seconds * c.fps));
    char buf[256];
    for (int64_t k = 0; k <= n; ++k)
    {
        const Pose T = cameraPoseAt(c, k);
        const Eigen::Quaterniond q(T.linear());
        const Eigen::Vector3d p = T.translation();
        std::snprintf(buf, sizeof buf, "%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", double(k) / c.fps, p.x(), p.y(),
                      p.z(), q.x(), q.y(), q.z(), q.w());
        out << buf;
    }
    io::writeFileAtomically(path, out.str());
}

VirtualFrames renderLoop(const VirtualCameraConfig& c)
{
    const sim::Scene scene = sim::makeTableWithChairsRoom();
    const CameraIntrinsics K = c.intrinsics();
    VirtualFrames f;
    sim::RenderedFrame r;
    const size_t n = size_t(c.width) * size_t(c.height);
    for (int i = 0; i < c.loop_frames; ++i)
    {
        sim::render(scene, cameraPoseAt(c, i), K, r, 8.0);
        std::vector<uint16_t> d(n);
        std::vector<uint8_t> rgb(3 * n);
        for (size_t p = 0; p < n; ++p)
        {
            const float z = r.depth.data[p];
            d[p] = z > 0 ? uint16_t(std::lround(z * 1000.0)) : 0;
            // A colour per class, shaded by distance: enough texture to look at.
            const uint32_t h = (uint32_t(r.semantic.data[p]) * 2654435761u) ^ (r.instance.data[p] * 40503u);
            const double shade = z > 0 ? std::max(0.3, 1.0 - z / 8.0) : 0.0;
            rgb[3 * p + 0] = uint8_t(shade * (64 + (h & 0xbf)));
            rgb[3 * p + 1] = uint8_t(shade * (64 + ((h >> 8) & 0xbf)));
            rgb[3 * p + 2] = uint8_t(shade * (64 + ((h >> 16) & 0xbf)));
        }
        f.depth_mm.push_back(std::move(d));
        f.rgb.push_back(std::move(rgb));
    }
    return f;
}

}  // namespace pndt::oni_virtual
