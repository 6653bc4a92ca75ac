// pndt-generate: writes a synthetic panoptic RGB-D dataset (rawlog, nicr layout with
// EMSANet-style predictions, 3D ground truth) and prints how good the simulated
// segmentation input is (per-frame mIoU / PQ), so every map result can be read against it.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <pndt/app/cli_numbers.h>
#include <pndt/data/dataset.h>
#include <pndt/sim/indoor_scene.h>

#include <exception>

using namespace pndt;

int main(int argc, char** argv)
{
    data::GeneratorOptions g;
    data::OutputOptions out;
    out.out_dir = "out/generated";
    std::string formats = "rawlog,nicr,gt";
    std::string walk = "handheld";
    bool verbose = false;

    std::string presets;
    for (const auto& n : sim::indoorScenePresetNames()) presets += (presets.empty() ? "" : ", ") + n;
    CLI::App app{
        "pndt-generate: synthetic indoor RGB-D sequences with panoptic ground truth and "
        "network-like segmentation noise"};
    app.add_option("--scene", g.scene, "scene preset (" + presets + ") or a number (random room from that seed)")
        ->capture_default_str();
    app.add_option("-n,--frames", g.frames, "frames along one loop through the room")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000000));
    app.add_option("--resolution", g.resolution,
                   "640x480 (ScanNet-like, max 10 m) or 1024x768 (Hypersim-like, max 20 m)")
        ->capture_default_str()
        ->check(CLI::IsMember({"640x480", "1024x768"}));
    app.add_option("--seg-noise", g.seg_noise, "segmentation noise strength (0 = perfect labels, 1 = network-like)")
        ->capture_default_str()
        ->check(app::kNonNegative);
    app.add_option("--depth-noise", g.depth_noise, "depth noise strength (0 = exact, 1 = Kinect-like)")
        ->capture_default_str()
        ->check(app::kNonNegative);
    app.add_option("--pose-noise", g.pose_noise, "pose noise strength of the written poses (0 = true poses)")
        ->capture_default_str()
        ->check(app::kNonNegative);
    app.add_option("--seed", g.seed, "seed of the recording (camera path and all noise)")->capture_default_str();
    app.add_option("--walk", walk, "handheld or robot camera path")
        ->capture_default_str()
        ->check(CLI::IsMember({"handheld", "robot"}));
    app.add_option("--laps", g.laps, "loops around the room over all frames")
        ->capture_default_str()
        ->check(app::kPositive);
    app.add_option("-o,--out", out.out_dir, "output folder")->capture_default_str();
    app.add_option("--formats", formats, "comma-separated subset of rawlog, nicr, gt (or all)")->capture_default_str();
    app.add_option("--split", out.split, "nicr split folder name")->capture_default_str();
    app.add_option("--threads", out.threads, "1 = single thread, 2 = write while generating the next frame")
        ->capture_default_str()
        ->check(CLI::Range(1, 2));
    app.add_flag("-v,--verbose", verbose, "print one line per frame");
    CLI11_PARSE(app, argc, argv);

    try
    {
        data::parseFormats(formats, out);
        g.walk = walk == "robot" ? sim::WalkStyle::Robot : sim::WalkStyle::Handheld;
        fmt::print("pndt-generate: scene '{}', {} frames {}, seed {}, noise seg {} / depth {} / pose {}\n", g.scene,
                   g.frames, g.resolution, g.seed, g.seg_noise, g.depth_noise, g.pose_noise);
        if (verbose) fmt::print("{:>6} {:>7} {:>6} {:>5} {:>5} {:>7}\n", "frame", "mIoU", "PQ", "objs", "wrong", "ph");
        const auto rep =
            data::generateDataset(g, out,
                                  [&](const data::GeneratedFrame& f, const data::QuickScores& s)
                                  {
                                      if (!verbose) return;
                                      int wrong = 0;
                                      for (const auto& o : f.prediction.outcomes)
                                          wrong += o.dropped || o.confused || o.split || o.merged ? 1 : 0;
                                      fmt::print("{:>6} {:>7.1f} {:>6.1f} {:>5} {:>5} {:>7}\n", f.id, s.miou, s.pq,
                                                 f.prediction.outcomes.size(), wrong, f.prediction.phantoms);
                                  });
        fmt::print("scene      : {} ({} objects, {} primitives)\n", rep.scene, rep.objects, rep.primitives);
        fmt::print("sequence   : {} ({} frames)\n", rep.sequence, rep.frames);
        if (!rep.rawlog_path.empty()) fmt::print("rawlog     : {}\n", rep.rawlog_path);
        if (!rep.nicr_split_dir.empty())
            fmt::print("nicr       : {} (sequence {}), predictions {}\n", rep.nicr_split_dir, rep.sequence,
                       rep.nicr_predictions_dir);
        if (!rep.gt_ply_path.empty())
            fmt::print("3D GT      : {} ({} points) + {} label files\n", rep.gt_ply_path, rep.gt_points,
                       rep.gt_txt_paths.size());
        fmt::print("summary    : {}\n", rep.summary_path);
        fmt::print(
            "raw input  : per-frame mIoU {:.1f}  PQ {:.1f}  (mean of {} frames; accumulated: mIoU {:.1f}  PQ {:.1f})\n",
            rep.raw_frame_mean.miou, rep.raw_frame_mean.pq, rep.frames, rep.raw_total.miou, rep.raw_total.pq);
        fmt::print("time       : {:.1f} s\n", rep.seconds);
        return 0;
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-generate: error: {}\n", e.what());
        return 1;
    }
}
