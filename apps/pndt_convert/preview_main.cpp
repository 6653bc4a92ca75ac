// pndt-rawlog-preview: maps a design §5 rawlog (e.g. written by pndt-convert) into a
// pndt::PanopticNDTMap — each scan with the latest CObservationRobotPose — and writes PNG views:
//   <prefix>_first_camera.png  measured depth of the first scan | the map rendered from that camera
//                              (same turbo colour map over depth)
//   <prefix>_overview.png      the map from an elevated viewpoint, coloured by height
// and prints scan/voxel counts, timings and the measured-vs-rendered depth agreement.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <opencv2/imgproc.hpp>
#include <pndt/app/map_outputs.h>

#include <chrono>
#include <filesystem>

#include "progress.h"
#include "rawlog_map.h"

using namespace pndt;
using namespace pndt::convert;

int main(int argc, char** argv)
{
    CLI::App app{"pndt-rawlog-preview: map a rawlog with PanopticNDTMap and write PNG views of the result"};
    std::string input, prefix = "preview";
    MapOptions mo;
    std::vector<double> up_v;
    double elevation = 50, tol_abs = 0.05, tol_rel = 0.02;
    size_t max_scans = 0;
    bool quiet = false;
    app.add_option("rawlog", input, "rawlog to map")->required();
    app.add_option("-o,--prefix", prefix, "output prefix of the PNGs")->capture_default_str();
    app.add_option("--voxel", mo.voxel_size, "voxel size, metres")->capture_default_str();
    app.add_option("--max-range", mo.max_range, "metres")->capture_default_str();
    app.add_option("--max-scans", max_scans, "map at most this many scans (0 = all)")->capture_default_str();
    app.add_option("--up", up_v, "world up direction x y z (default: the first camera's up)")->expected(3);
    app.add_option("--elevation", elevation, "overview elevation angle, degrees")->capture_default_str();
    app.add_option("--tol-abs", tol_abs, "depth agreement tolerance, metres")->capture_default_str();
    app.add_option("--tol-rel", tol_rel, "... plus this fraction of the depth")->capture_default_str();
    app.add_flag("-q,--quiet", quiet, "no progress output");
    CLI11_PARSE(app, argc, argv);

    try
    {
        mo.validate();
        // Checked before anything is read or written (an unchecked --up failed after mapping, in
        // lookAt, naming no option, with a PNG left behind).
        if (up_v.size() == 3)
        {
            const Eigen::Vector3d u(up_v[0], up_v[1], up_v[2]);
            if (!u.allFinite() || !(u.norm() >= 1e-9))
                throw std::runtime_error(fmt::format("--up: \"{} {} {}\" is not a direction (three finite numbers, "
                                                     "not all zero)",
                                                     up_v[0], up_v[1], up_v[2]));
        }
        if (!(elevation > 0 && elevation <= 90))  // 90: straight down
            throw std::runtime_error(
                fmt::format("--elevation: {} is not an angle above the horizon (more than 0, at most 90 degrees)",
                            elevation));
        if (!(tol_abs >= 0 && std::isfinite(tol_abs)) || !(tol_rel >= 0 && std::isfinite(tol_rel)))
            throw std::runtime_error(
                fmt::format("--tol-abs / --tol-rel: {} / {} are not tolerances (finite, >= 0)", tol_abs, tol_rel));
        if (!std::filesystem::is_regular_file(input)) throw std::runtime_error(input + ": rawlog not found");
        PanopticNDTMap map(mo);
        ProgressBar bar("scans", 0, quiet ? ProgressBar::Mode::Silent : ProgressBar::Mode::Auto);
        const auto t0 = std::chrono::steady_clock::now();
        RawlogMapOptions ro;
        ro.max_scans = max_scans;
        const RawlogMapResult r = mapRawlog(input, map, ro, [&](size_t n) { bar.update(n); });
        bar.finish();
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (r.scans_mapped == 0)
            throw std::runtime_error(fmt::format("{}: no scan to map: {} scans, {} robot poses, none of the scans "
                                                 "with a robot pose at most {} s after it",
                                                 input, r.scans, r.robot_poses, ro.pose_max_gap));

        const PanopticMap& core = map.core();
        const Pose& T0 = r.cameras.front();
        const Eigen::Vector3d up =
            up_v.size() == 3 ? Eigen::Vector3d(up_v[0], up_v[1], up_v[2]).normalized() : Eigen::Vector3d(-T0.linear().col(1));
        const CameraIntrinsics& K = r.first_frame.K;

        RenderedView v;
        core.render(T0, K, v);
        const DepthAgreement a = compareDepth(r.first_frame.depth, v.depth, tol_abs, tol_rel);
        double dmax = 0.1;
        for (float d : r.first_frame.depth.data)
            if (d > 0 && std::isfinite(d)) dmax = std::max(dmax, double(d));
        cv::Mat both;
        cv::hconcat(colorizeDepth(r.first_frame.depth, 0.0, dmax), colorizeDepth(v.depth, 0.0, dmax), both);
        const std::string png_first = prefix + "_first_camera.png", png_over = prefix + "_overview.png";
        const auto parent = std::filesystem::path(prefix).parent_path();
        if (!parent.empty()) std::filesystem::create_directories(parent);
        writePng(both, png_first);
        const auto [hmin, hmax] = heightRange(core, up);
        const CameraIntrinsics K_over = app::overviewIntrinsics();  // the frames' camera may show nothing from there
        writePng(renderHeightView(core, overviewCamera(core, r.cameras, up, K_over, elevation), K_over, up, hmin, hmax),
                 png_over);

        fmt::print("pndt-rawlog-preview: {}\n", input);
        fmt::print("  objects read       : {} ({} robot poses, {} scans, {} label images, {} other)\n", r.objects,
                   r.robot_poses, r.scans, r.label_images, r.other_objects);
        fmt::print("  scans mapped       : {} ({} without a matching robot pose)\n", r.scans_mapped,
                   r.scans_without_pose);
        fmt::print("  map                : {}\n", map.asString());
        fmt::print("  voxels             : {} ({} occupied), {:.1f} MB\n", core.voxels().size(), core.occupiedCount(),
                   core.memoryBytes() / 1e6);
        fmt::print("  time               : {:.2f} s total, {:.2f} s reading, {:.2f} s mapping ({:.1f} scans/s)\n", wall,
                   r.seconds_read, r.seconds_map, r.scans_mapped / std::max(1e-9, r.seconds_map));
        fmt::print("  first camera       : {:.1f} % of measured pixels rendered, {:.1f} % within {:.3f} m + {:.1f} %, "
                   "median |error| {:.4f} m\n",
                   100 * a.coverage(), 100 * a.agreeFraction(), tol_abs, 100 * tol_rel, a.median_abs_error);
        fmt::print("  up                 : ({:+.3f}, {:+.3f}, {:+.3f}); heights {:.2f} .. {:.2f} m\n", up.x(), up.y(),
                   up.z(), hmin, hmax);
        fmt::print("  wrote              : {}, {}\n", png_first, png_over);
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-rawlog-preview: error: {}\n", e.what());
        return 1;
    }
    return 0;
}
