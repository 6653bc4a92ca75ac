// pndt-convert: RGB-D sequence folder (Redwood/Open3D, TUM RGB-D, nicr-scene-analysis-datasets with
// optional EMSANet predictions) → MRPT rawlog (design §5), see convert.h and doc/redwood.md.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <pndt/mrpt/map_files.h>

#include <fstream>

#include "convert.h"
#include "progress.h"

using namespace pndt;
using namespace pndt::convert;

int main(int argc, char** argv)
{
    CLI::App app{
        "pndt-convert: convert an RGB-D sequence folder into an MRPT rawlog for PanopticNDT.\n"
        "Per frame: CObservationRobotPose, CObservation3DRangeScan and, with labels, the two float32\n"
        "<label>_PANOPTIC_SEMANTIC / _PANOPTIC_INSTANCE CObservationImages. Frames without a pose are\n"
        "skipped and counted. Inputs: Redwood/Open3D, TUM RGB-D, nicr-scene-analysis-datasets folders."};
    ConvertOptions o;
    std::string sensor_pose, progress_mode = "auto", summary_json;
    bool no_color = false, quiet = false;
    int progress_step = 10;
    double depth_scale = 0;

    app.add_option("input", o.input, "sequence folder (nicr: the split folder, e.g. .../scannet/valid)")->required();
    app.add_option("-o,--output", o.output, "output rawlog (written atomically)")->required();
    app.add_option("--format", o.format, "auto | redwood | tum | nicr")->capture_default_str();

    auto* g_nicr = app.add_option_group("nicr-scene-analysis-datasets");
    g_nicr->add_option("--sequence", o.sequence, "<seq> under depth/ (e.g. structureio_968x1296/scene0000_00)");
    g_nicr->add_option("--predictions", o.predictions_dir,
                       "EMSANet mapping output folder (pred_panoptic_semantic/, pred_panoptic_instance/)");
    g_nicr->add_option("--labels", o.labels,
                       "auto | predictions | gt | model | none (auto: model or predictions if given)")
        ->capture_default_str();
    g_nicr->add_option("--semantic-dir", o.semantic_dir, "GT semantic folder (default: semantic_40, ...)");
    g_nicr->add_option("--instance-dir", o.instance_dir, "GT instance folder (default: instance, ...)");

    auto* g_seg = app.add_option_group("segmentation front-end (any format)");
    g_seg->add_option("--model", o.model,
                      "label every frame with this model description (JSON beside an .onnx, doc/segmentation.md)");
    g_seg->add_option("--up", o.up_world,
                      "gravity up \"x y z\" in the poses' world frame (detector planes, --level; default: camera -y)");
    g_seg->add_flag("--level", o.level,
                    "write the poses in a world turned so that --up (default: the world axis nearest the first "
                    "frame's up) is +z: floor plans, pndt-nav and MRPT's 2D tools take world z as up");

    auto* g_in = app.add_option_group("input");
    auto* depth_scale_opt = g_in->add_option("--depth-scale", depth_scale, "depth units per metre (default: 1000; TUM 5000)");
    g_in->add_option("--frame-rate", o.frame_rate_hz, "Hz, stamps of stampless sequences (t = i / rate)")
        ->capture_default_str();
    g_in->add_option("--intrinsics", o.intrinsics_file, "Open3D intrinsics JSON overriding the folder's");
    g_in->add_option("--start", o.start, "first frame index")->capture_default_str();
    g_in->add_option("--stride", o.stride, "use every n-th frame")->capture_default_str();
    g_in->add_option("--max-frames", o.max_frames, "at most this many frames (0 = all)")->capture_default_str();
    g_in->add_flag("--skip-bad-frames", o.skip_bad_frames,
                   "count and skip frames whose images are unreadable or of the wrong size (default: error)");

    auto* g_pose = app.add_option_group("poses");
    g_pose->add_option("--poses", o.poses_file, "external pose file (default: the sequence's own poses)");
    g_pose->add_option("--pose-format", o.pose_format,
                       "tum | rtabmap0 | rtabmap1 | rtabmap2 | rtabmap4 | rtabmap10 | rtabmap11 | redwood | nicr "
                       "(also kitti)");
    g_pose->add_option("--pose-frame", o.pose_frame,
                       "auto | camera | robot: poses of the optical camera or of the robot body "
                       "(auto: robot for rtabmap*, else camera)")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "camera", "robot"}));  // checked whether or not --poses is given
    g_pose->add_option("--pose-match", o.pose_match,
                       "auto | time | index (auto: index for stampless formats, else time)")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "time", "index"}));
    g_pose->add_option("--max-pose-gap", o.max_pose_gap, "s, largest gap between poses to interpolate across")
        ->capture_default_str();
    g_pose->add_option("--pose-time-offset", o.pose_time_offset, "s, added to frame stamps before the lookup")
        ->capture_default_str();
    g_pose->add_option("--pose-index-offset", o.pose_index_offset, "frame i takes pose i + offset (index mode)")
        ->capture_default_str();
    g_pose->add_flag("--strict-poses", o.strict_poses, "non-finite poses are errors (default: skipped, counted)");
    g_pose->add_option("--sensor-pose", sensor_pose,
                       "robot -> depth camera \"x y z yaw pitch roll\" (m, deg; MRPT sensor axes)");

    auto* g_out = app.add_option_group("output");
    g_out->add_option("--stamp-offset", o.stamp_offset,
                      "s, added to every written stamp (Redwood/nicr stamps are i / frame rate otherwise)")
        ->capture_default_str();
    g_out->add_option("--label", o.rgbd_label, "sensorLabel of the range scans")->capture_default_str();
    g_out->add_option("--pose-label", o.pose_label, "sensorLabel of the robot poses")->capture_default_str();
    g_out->add_flag("--no-color", no_color, "do not embed colour images");
    g_out->add_option("--jpeg-quality", o.color_jpeg_quality, "colour JPEG quality 1..100, 0 = raw (lossless)")
        ->capture_default_str();
    g_out->add_option("--gz-level", o.gz_level, "gzip level 0..9")->capture_default_str();
    g_out->add_option("--summary-json", summary_json, "also write the summary as JSON");
    g_out->add_option("--progress", progress_mode, "auto | bar | lines | none (stderr)")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "bar", "lines", "none"}));  // also with -q
    g_out->add_option("--progress-step", progress_step, "percent between progress lines when not a terminal")
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
    g_out->add_flag("-q,--quiet", quiet, "no progress output");

    CLI11_PARSE(app, argc, argv);

    try
    {
        if (depth_scale_opt->count()) o.depth_units_per_metre = depth_scale;  // 0 given is an error, not the default
        if (!sensor_pose.empty()) o.sensor_pose = parseSensorPose(sensor_pose);
        o.color = !no_color;

        ProgressBar::Mode mode = ProgressBar::Mode::Auto;
        if (quiet || progress_mode == "none")
            mode = ProgressBar::Mode::Silent;
        else if (progress_mode == "bar")
            mode = ProgressBar::Mode::Bar;
        else if (progress_mode == "lines")
            mode = ProgressBar::Mode::Lines;
        else if (progress_mode != "auto")
            throw InputError(fmt::format("--progress must be auto, bar, lines or none (got '{}')", progress_mode));

        std::unique_ptr<ProgressBar> bar;
        const ConvertReport r = convertSequence(o, [&](size_t done, size_t total) {
            if (!bar) bar = std::make_unique<ProgressBar>("frames", total, mode, stderr, progress_step);
            bar->update(done);
        });
        if (bar) bar->finish();
        fmt::print("{}\n", formatReport(r, o));
        if (!summary_json.empty())
            io::writeFileAtomically(summary_json, [&](const std::string& tmp) {
                std::ofstream f(tmp);
                f << reportJson(r, o) << "\n";
                if (!f) throw std::runtime_error("cannot write " + tmp);
            });
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-convert: error: {}\n", e.what());
        return 1;
    }
    return 0;
}
