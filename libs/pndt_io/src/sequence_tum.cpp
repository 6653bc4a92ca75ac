// TUM RGB-D folders.
#include "fs_util.h"
#include "text_util.h"

#include <pndt/io/pose_interpolator.h>
#include <pndt/io/sequence.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <tuple>

namespace pndt::io
{
namespace
{
struct Stamped
{
    double t;
    std::string path;
};

struct Assoc
{
    double t_depth;
    std::string depth, color;
};

/// TUM list file: `timestamp filename` lines, '#' comments.
std::vector<Stamped> readTumList(const std::string& dir, const std::string& file)
{
    detail::LineReader in(file);
    std::vector<Stamped> out;
    std::string line;
    while (in.next(line))
    {
        if (detail::isBlankOrComment(line)) continue;
        const auto tok = detail::splitWs(line);
        if (tok.size() != 2)
            detail::failLine(file, in.lineNo(),
                             fmt::format("expected 2 values (timestamp filename), got {}", tok.size()));
        double t;
        if (!detail::parseDouble(tok[0], t) || !std::isfinite(t))
            detail::failLine(file, in.lineNo(), fmt::format("timestamp '{}' is not a number", tok[0]));
        out.push_back({t, detail::joinPath(dir, std::string(tok[1]))});
    }
    return out;
}

bool underDepthFolder(std::string_view p)
{
    return p.rfind("depth/", 0) == 0 || p.rfind("./depth/", 0) == 0 ||
           p.find("/depth/") != std::string_view::npos;
}

std::vector<Assoc> readAssociationFile(const std::string& dir, const std::string& file,
                                       double frame_rate_hz)
{
    detail::LineReader in(file);
    std::vector<Assoc> out;
    std::string line;
    size_t index = 0, previous_line = 0;
    while (in.next(line))
    {
        if (detail::isBlankOrComment(line)) continue;
        const auto tok = detail::splitWs(line);
        Assoc a;
        if (tok.size() == 4)
        {
            double t1, t2;
            if (!detail::parseDouble(tok[0], t1) || !std::isfinite(t1))
                detail::failLine(file, in.lineNo(), fmt::format("timestamp '{}' is not a number", tok[0]));
            if (!detail::parseDouble(tok[2], t2) || !std::isfinite(t2))
                detail::failLine(file, in.lineNo(), fmt::format("timestamp '{}' is not a number", tok[2]));
            const bool first_is_depth = underDepthFolder(tok[1]) && !underDepthFolder(tok[3]);
            if (first_is_depth)
                a = {t1, detail::joinPath(dir, std::string(tok[1])), detail::joinPath(dir, std::string(tok[3]))};
            else
                a = {t2, detail::joinPath(dir, std::string(tok[3])), detail::joinPath(dir, std::string(tok[1]))};
        }
        else if (tok.size() == 2)
        {
            // Open3D rgbd.match: `depth colour`, no stamps.
            a.depth = detail::joinPath(dir, std::string(tok[0]));
            a.color = detail::joinPath(dir, std::string(tok[1]));
            const std::string s = detail::stem(a.depth);
            double t;
            if (s.find('.') != std::string::npos && detail::parseDouble(s, t) && std::isfinite(t))
                a.t_depth = t;
            else
                a.t_depth = static_cast<double>(index) / frame_rate_hz;
        }
        else
        {
            detail::failLine(file, in.lineNo(),
                             fmt::format("expected 4 values (t_rgb rgb_file t_depth depth_file) or 2 "
                                         "(depth_file colour_file), got {}",
                                         tok.size()));
        }
        // Poses are looked up and maps handed over by frame time: a file out of order (or with a
        // line twice) made a rawlog whose poses pndt-map refuses, blaming the rawlog.
        if (!out.empty() && !(a.t_depth > out.back().t_depth))
            detail::failLine(file, in.lineNo(),
                             fmt::format("depth stamp {:.6f} is not after the one of line {} ({:.6f}): the frames must "
                                         "be in time order, each once (sort the file by time, drop repeated lines)",
                                         a.t_depth, previous_line, out.back().t_depth));
        previous_line = in.lineNo();
        if (!detail::isRegularFile(a.depth))
            detail::failLine(file, in.lineNo(), fmt::format("depth file '{}' not found", a.depth));
        if (!detail::isRegularFile(a.color))
            detail::failLine(file, in.lineNo(), fmt::format("colour file '{}' not found", a.color));
        out.push_back(std::move(a));
        ++index;
    }
    return out;
}

/// Greedy nearest-stamp association, each image used at most once.
std::vector<Assoc> associate(const std::vector<Stamped>& rgb, const std::vector<Stamped>& depth,
                             double max_dt)
{
    std::vector<Stamped> rgb_sorted = rgb;
    std::sort(rgb_sorted.begin(), rgb_sorted.end(),
              [](const Stamped& a, const Stamped& b) { return a.t < b.t; });
    std::vector<std::tuple<double, size_t, size_t>> cand;  // |dt|, depth index, rgb index
    for (size_t i = 0; i < depth.size(); ++i)
    {
        const double t = depth[i].t;
        auto it = std::lower_bound(rgb_sorted.begin(), rgb_sorted.end(), t - max_dt,
                                   [](const Stamped& s, double v) { return s.t < v; });
        for (; it != rgb_sorted.end() && it->t <= t + max_dt; ++it)
            cand.emplace_back(std::abs(it->t - t), i, static_cast<size_t>(it - rgb_sorted.begin()));
    }
    std::sort(cand.begin(), cand.end());
    std::vector<bool> used_d(depth.size(), false), used_c(rgb_sorted.size(), false);
    std::vector<Assoc> out;
    for (const auto& [dt, i, j] : cand)
    {
        (void)dt;
        if (used_d[i] || used_c[j]) continue;
        used_d[i] = used_c[j] = true;
        out.push_back({depth[i].t, depth[i].path, rgb_sorted[j].path});
    }
    std::sort(out.begin(), out.end(), [](const Assoc& a, const Assoc& b) { return a.t_depth < b.t_depth; });
    return out;
}
}  // namespace

RgbdSequence openTumSequence(const std::string& dir, const TumOptions& options)
{
    if (!detail::isDirectory(dir)) detail::failFile(dir, "TUM sequence folder not found");
    if (!(options.frame_rate_hz > 0) || !std::isfinite(options.frame_rate_hz))
        detail::failFile(dir, fmt::format("frame_rate_hz must be > 0 (got {})", options.frame_rate_hz));

    RgbdSequence seq;
    seq.source = dir;
    seq.kind = "tum";
    seq.depth_units_per_metre = options.depth_units_per_metre;

    std::vector<Assoc> frames;
    std::string assoc_file;
    if (!options.associations_file.empty())
    {
        assoc_file = detail::joinPath(dir, options.associations_file);
        detail::requireRegularFile(assoc_file);
    }
    else
    {
        for (const char* n : {"associations.txt", "association.txt", "associate.txt", "rgbd.match"})
        {
            if (detail::isRegularFile(detail::joinPath(dir, n)))
            {
                assoc_file = detail::joinPath(dir, n);
                break;
            }
        }
    }
    if (!assoc_file.empty())
        frames = readAssociationFile(dir, assoc_file, options.frame_rate_hz);
    else
    {
        const std::string rgb_txt = detail::joinPath(dir, "rgb.txt");
        const std::string depth_txt = detail::joinPath(dir, "depth.txt");
        if (!detail::isRegularFile(rgb_txt) || !detail::isRegularFile(depth_txt))
            detail::failFile(dir, "no association file (associations.txt, rgbd.match, ...) and no "
                                  "rgb.txt + depth.txt to associate");
        frames = associate(readTumList(dir, rgb_txt), readTumList(dir, depth_txt),
                           options.max_association_dt);
    }
    if (frames.empty()) detail::failFile(dir, "no RGB-D frames found");

    CameraIntrinsics K;
    if (options.intrinsics)
        K = *options.intrinsics;
    else
    {
        K.width = 640;
        K.height = 480;
        K.fx = K.fy = 525.0;
        K.cx = 319.5;
        K.cy = 239.5;
    }
    if (!K.valid()) detail::failFile(dir, "invalid camera intrinsics");

    PoseInterpolator gt;
    const std::string gt_file =
        options.groundtruth_file.empty() ? std::string() : detail::joinPath(dir, options.groundtruth_file);
    const bool have_gt = !gt_file.empty() && detail::isRegularFile(gt_file);
    if (have_gt)
    {
        PoseReadReport report;
        auto poses = readTumPoses(gt_file, {}, &report);
        seq.non_finite_poses = report.skipped_non_finite;
        try
        {
            gt = PoseInterpolator(std::move(poses));
        }
        catch (const InputError& e)
        {
            detail::failFile(gt_file, e.what());
        }
    }

    for (const auto& a : frames)
    {
        FrameRecord r;
        r.t = a.t_depth;
        r.id = detail::stem(a.depth);
        r.depth_path = a.depth;
        r.color_path = a.color;
        r.K = K;
        r.K_color = K;
        if (have_gt) r.T_world_cam = gt.at(r.t, options.max_pose_gap);
        if (!r.T_world_cam) ++seq.frames_without_pose;
        seq.frames.push_back(std::move(r));
    }
    return seq;
}

bool isTumFolder(const std::string& dir)
{
    const auto file = [&](const char* name) { return std::filesystem::is_regular_file(std::filesystem::path(dir) / name); };
    return (file("rgb.txt") && file("depth.txt")) || file("associations.txt") || file("association.txt") ||
           file("associate.txt");
}

RgbdSequence openRecordingFolder(const std::string& dir)
{
    return isTumFolder(dir) ? openTumSequence(dir) : openRedwoodSequence(dir);
}
}  // namespace pndt::io
