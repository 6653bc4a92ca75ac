// pndt-map: replays a rawlog of RGB-D + panoptic observations with poses from an
// external localiser into rolling short-term panoptic maps (design §6-7).
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/system/datetime.h>
#include <pndt/app/cli_numbers.h>
#include <pndt/app/error_text.h>
#include <pndt/app/layered_config.h>
#include <pndt/app/map_config.h>
#include <pndt/app/map_rawlog.h>
#include <pndt/app/map_outputs.h>
#include <pndt/app/observation_stream.h>
#include <pndt/app/pose_refinement.h>
#include <pndt/app/pose_track.h>
#include <pndt/app/progress_bar.h>
#include <pndt/app/read_ahead_stream.h>
#include <pndt/app/short_term_maps.h>
#include <pndt/app/world_up.h>
#include <pndt/io/atomic_file.h>
#include <pndt/mrpt/observation_pairer.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <limits>

#include "dataset_source.h"
#include "mapper_settings.h"
#include "refine_cli.h"
#include "short_term_cli.h"

using namespace pndt;
using namespace pndt::app;
namespace fs = std::filesystem;

namespace
{
std::atomic<bool> g_stop{false};
extern "C" void onSignal(int) { g_stop = true; }

/// Exit codes: 0 ok, 1 error, 2 input truncated (what could be read was mapped), 130 interrupted.
constexpr int kExitError = 1, kExitTruncated = 2, kExitInterrupted = 130;
// An output file could not be written (disk full, read-only, permissions): mapping stopped;
// the maps already listed in index.json are complete (doc/hardening.md).
constexpr int kExitWriteFailed = 3;

/// An optical camera pose looking from `eye` at `target`, world z up.
Pose lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target)
{
    const Eigen::Vector3d z = (target - eye).normalized();
    Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
    if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitX();
    x.normalize();
    const Eigen::Vector3d y = z.cross(x);
    Pose T = Pose::Identity();
    T.linear() << x, y, z;
    T.translation() = eye;
    return T;
}

/// The summary's list of what this run wrote, as the settings named it.
std::string outputsLine(const ShortTermOptions& o, const ShortTermMaps& maps)
{
    const std::string d = o.out_dir + "/";
    std::string line = fmt::format("{0}index.json, {0}{1}_*.pndt.gz", d, o.prefix);
    if (o.write_ply) line += fmt::format(", {}{}_*.ply", d, o.prefix);
    if (const MapRawlogWriter* r = maps.rawlog())
        line += ", " + (r->segmented() ? fmt::format("{}maps-NNNN.rawlog", d) : r->path());
    return line + fmt::format(", {0}instances.json, {0}view_last_*.png, {0}view_overview_*.png, {0}floor_plan.png", d);
}

size_t peakRssBytes()
{
    std::ifstream f("/proc/self/status");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind("VmHWM:", 0) == 0) return size_t(std::stoul(line.substr(6))) * 1024;
    return 0;
}
}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"pndt-map: replay a rawlog into short-term panoptic NDT maps"};
    std::vector<std::string> inputs;
    std::string out_dir = "out/map", poses, pose_format;
    std::vector<std::string> presets;
    std::vector<std::string> configs, sets;
    double period = -1, voxel_size = 0;
    int max_frames = 0;
    bool no_progress = false, view = false;
    std::string screenshot, mesh_screenshot;
    DatasetOptions dataset;
    app.add_option("input", inputs,
                   "rawlog (CObservation3DRangeScan + panoptic CObservationImages [+ CObservationRobotPose]); several "
                   "rawlogs are replayed one after the other, in time order (a recording cut into files: "
                   "rec-*.rawlog); or a dataset folder with --input-format")
        ->required();
    app.add_option("--input-format", dataset.format, "dataset folder: redwood, tum or nicr")
        ->check(CLI::IsMember({"redwood", "tum", "nicr"}));
    app.add_option("--nicr-sequence", dataset.nicr_sequence, "nicr: sequence inside the split folder");
    app.add_option("--predictions", dataset.predictions, "nicr: EMSANet mapping export (labels)");
    app.add_flag("--gt-labels", dataset.ground_truth_labels, "nicr: ground truth as labels");
    app.add_option("-o,--out", out_dir, "output folder")->capture_default_str();
    app.add_option("-p,--preset", presets,
                   "preset from config/presets, layered in the order given (repeatable or comma-separated; "
                   "paper = the paper's rules exactly; detector = thresholds for the detector front-end's scores)")
        ->delimiter(',')
        ->check(CLI::IsMember({"scannet", "hypersim", "realworld", "paper", "detector"}));
    app.add_option("-c,--config", configs, ".ini files layered over the defaults (repeatable)");
    app.add_option("-s,--set", sets, "override: section.key=value (repeatable)");
    app.add_option("--poses", poses, "external pose file (sets pose_source=file)");
    app.add_option("--pose-format", pose_format,
                   "tum, rtabmap1/10/11, nicr (by stamp); rtabmap0/2/4, kitti, redwood (no stamps: the k-th depth "
                   "frame takes the k-th pose)");
    std::string clock_offset;
    app.add_option("--clock-offset", clock_offset,
                   "seconds added to pose stamps (localiser clock -> camera clock; config clock_offset; what "
                   "--refine's time offset estimate suggests)")
        ->type_name("SECONDS");
    // Given values go to the config, whose checks name the key and its range; a value that
    // is not finite or out of range is an error, never "not given".
    CLI::Option* period_opt = app.add_option("--period", period, "short-term map period (config period_unit; 0 = one map)")
                                  ->check(app::kNonNegative);
    CLI::Option* voxel_opt = app.add_option("--voxel-size", voxel_size, "voxel size in metres")->check(app::kPositive);
    app.add_option("--max-frames", max_frames, "stop after this many mapped frames (0 = all)")
        ->check(app::kNonNegative);
    ShortTermCli short_term_cli;
    short_term_cli.addTo(app);
    app.add_flag("--no-progress", no_progress, "no progress bar");
    RefineCli refine_cli;
    refine_cli.addTo(app);
    bool no_maps_rawlog = false, rawlog_inputs = false;
    app.add_flag("--no-maps-rawlog", no_maps_rawlog, "do not write maps.rawlog (config maps_rawlog)");
    app.add_flag("--rawlog-inputs", rawlog_inputs,
                 "interleave the input observations with the maps in maps.rawlog (config maps_rawlog_inputs)");
    app.add_option("--screenshot", screenshot, "PNG of the final map's 3D view, rendered off-screen");
    app.add_option("--mesh-screenshot", mesh_screenshot,
                   "PNG of the final map's voxel surfaces (exposed faces only), rendered off-screen");
    app.add_flag("--view", view, "open an interactive 3D view of the final map (needs a display)");
    CLI11_PARSE(app, argc, argv);

    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    const auto t_start = std::chrono::steady_clock::now();
    try
    {
        // ---- configuration: defaults, preset, user files, then overrides
        const std::string config = configDir(PNDT_CONFIG_DIR);
        std::vector<std::string> files = {config + "/panoptic_ndt.ini", config + "/pndt_map.ini"};
        for (const auto& preset : presets) files.push_back(config + "/presets/" + preset + ".ini");
        files.insert(files.end(), configs.begin(), configs.end());
        if (!poses.empty()) sets.insert(sets.begin(), {"pndt-map.pose_source=file", "pndt-map.pose_file=" + poses});
        if (!pose_format.empty()) sets.push_back("pndt-map.pose_format=" + pose_format);
        if (!clock_offset.empty()) sets.push_back("pndt-map.clock_offset=" + clock_offset);
        if (period_opt->count()) sets.push_back(fmt::format("pndt-map.period={}", period));
        if (no_maps_rawlog) sets.push_back("pndt-map.maps_rawlog=false");
        if (rawlog_inputs) sets.push_back("pndt-map.maps_rawlog_inputs=true");
        short_term_cli.addSetsTo(sets);
        if (voxel_opt->count()) sets.push_back(fmt::format("MAP_PanopticNDTMap_00_creationOpts.voxel_size={}", voxel_size));
        const auto cfg = loadLayeredConfig(files, sets);
        std::vector<std::string> sections;
        cfg.getAllSections(sections);
        for (const auto& s : sections)  // a typo in our sections must not be silently ignored
            if (s.rfind("MAP_PanopticNDTMap_", 0) == 0)
                rejectUnknownSections(cfg, {"pndt-map", "pndt-live", "MAP", "MAP_PanopticNDTMap_00_creationOpts",
                                            "MAP_PanopticNDTMap_00_insertOpts", "MAP_PanopticNDTMap_00_renderOpts"},
                                      {});
        rejectUnknownSections(cfg, {"pndt-map", "pndt-live", "MAP"}, {"MAP_"});  // [pndt-live]: pndt-live's own
        MapperSettings settings = MapperSettings::load(cfg);
        settings.short_term.out_dir = out_dir;
        io::parsePoseFormat(settings.pose_format);  // checked whether or not a pose file is read
        if (!pose_format.empty() && settings.pose_source != "file")
            throw std::runtime_error("--pose-format " + pose_format +
                                     " is the format of a pose file: give --poses FILE (the rawlog's own poses need "
                                     "none)");
        for (const auto& in : inputs)  // before anything is written: the run would truncate it
            if (const std::string problem = ownOutputProblem(settings.short_term, in); !problem.empty())
                throw std::runtime_error(problem);
        const auto factory = mapFactory(cfg);
        const auto prototype = factory();

        // ---- poses from the external localiser
        const bool folder = fs::is_directory(inputs[0]);
        if (folder && dataset.format.empty())
            throw std::runtime_error(inputs[0] + " is a folder: give --input-format redwood, tum or nicr");
        if (folder && inputs.size() > 1) throw std::runtime_error("give one dataset folder, or rawlogs only");
        // The input as messages name it: "rec-0000.rawlog .. rec-0003.rawlog (4 files)" for several.
        const std::string input = inputs.size() == 1 ? inputs[0]
                                                     : fmt::format("{} .. {} ({} files)", inputs.front(), inputs.back(),
                                                                   inputs.size());
        std::optional<PoseTrack> track;
        if (settings.pose_source == "file")
            track = PoseTrack::fromFile(settings.pose_file, io::parsePoseFormat(settings.pose_format),
                                        settings.pose_frame.empty() ? std::nullopt
                                                                    : std::optional(parsePoseFrame(settings.pose_frame)),
                                        settings.pose_max_gap);
        else if (!folder)  // the rawlog's own robot poses, taken while it is replayed
            track = PoseTrack::whileReading(input, settings.pose_label, settings.pose_max_gap);
        // else: the dataset's own per-frame poses
        if (track) track->setClockOffset(settings.clock_offset);
        const bool poses_in_stream = track && !folder && settings.pose_source != "file";

        fmt::print("pndt-map: {} ({}), {}\n", input,
                   !track            ? std::string("the dataset's poses")
                   : poses_in_stream ? std::string("the rawlog's robot poses")
                                     : fmt::format("{} poses from {}", track->size(), track->source()),
                   prototype->asString());
        if (settings.short_term.period > 0)
            fmt::print("short-term maps every {} {}, warm-up {:.0f}%\n", settings.short_term.period,
                       settings.short_term.period_in_frames ? "frames" : "s", settings.short_term.warmup * 100);

        // ---- replay (the input opened first: one that is missing leaves no output behind)
        std::optional<ReadAheadStream> stream;  // decoding overlaps with mapping
        std::optional<DatasetSource> source;
        if (folder)
            source.emplace(input, dataset);
        else
            stream.emplace(inputs);
        if (const std::string note = earlierRunNote(settings.short_term); !note.empty())
            fmt::print(stderr, "pndt-map: note: {}\n", note);
        ShortTermMaps maps(factory, settings.short_term);
        std::optional<FramePoseRefinement> refinement = refine_cli.make(settings);  // issue #22: against the localiser's errors
        ObservationPairer pairer;
        pairer.options = prototype->insertionOptions;
        ProgressBar bar("pndt-map", !no_progress);
        std::vector<PairedFrame> done;
        uint64_t observations = 0, scans = 0, mapped = 0, labelled = 0, no_pose = 0, other_sensor = 0, not_after = 0;
        // Poses are looked up and maps handed over by frame time: a depth frame stamped no
        // later than the one before (a camera clock that started again) is skipped, counted.
        double last_scan_t = -std::numeric_limits<double>::infinity();
        const auto inTimeOrder = [&](double t) {
            if (t > last_scan_t)
            {
                last_scan_t = t;
                return true;
            }
            if (not_after++ == 0)
                fmt::print(stderr, "\npndt-map: {}: depth frame {} at t={:.6f} s is not after the frame before "
                           "(t={:.6f} s; a camera clock reset?): frames out of time order are skipped and counted\n",
                           input, scans, t, last_scan_t);
            return false;
        };
        std::optional<PairedFrame> last;
        const auto atFrameLimit = [&] { return max_frames > 0 && mapped >= uint64_t(max_frames); };
        // The share of the work done: of the input read, or of --max-frames when that ends the run first.
        const auto done_share = [&](double input_read) {
            return max_frames > 0 ? std::max(input_read, double(mapped) / double(max_frames)) : input_read;
        };
        const auto integrateDone = [&] {
            for (PairedFrame& p : done)
            {
                if (atFrameLimit()) break;  // --max-frames: frames completed together are not all mapped
                const uint64_t budget_before = maps.budgetHandOvers();
                if (refinement)
                    p.T_world_cam = refinement->refine(maps.current() ? &maps.current()->core() : nullptr, p.frame,
                                                       p.T_world_cam, mrpt::Clock::toDouble(p.stamp));
                maps.integrate(p.frame, p.T_world_cam, mrpt::Clock::toDouble(p.stamp));
                if (maps.budgetHandOvers() != budget_before)
                    fmt::print(stderr, "\npndt-map: {} reached the size budget of {} voxels: written early, a new "
                               "short-term map started\n",
                               maps.index().back().file, settings.short_term.max_voxels);
                ++mapped;
                labelled += p.labelled;
                // Its images take the next scan (a folder's frames are loaded afresh, never paired).
                if (last && stream) pairer.recycle(std::move(*last));
                last = std::move(p);
            }
            done.clear();
        };
        const auto more = [&] { return !g_stop && !atFrameLimit(); };
        // A scan takes its pose once the track reaches its time: with the rawlog's own
        // poses, scans after the last pose read so far wait (bounded) for the next one.
        constexpr size_t kMaxWaitingScans = 64;
        std::deque<mrpt::obs::CObservation3DRangeScan::Ptr> waiting;
        CameraUpTally camera_up;  // the pictures and pndt-nav take world z as up: said when it is not
        // The up of the poses' own frame in the camera: a robot's z (through its camera's mount), a camera's -y.
        const auto upInCamera = [&](const mrpt::poses::CPose3D& extrinsic) {
            return track && track->frame() == PoseFrame::Robot ? robotUpInCamera(extrinsic) : opticalUp();
        };
        // `ordinal`: the scan's place among the input's depth frames (0-based), which finds
        // its pose in a stampless pose file (a track by index).
        const auto placeScan = [&](const mrpt::obs::CObservation3DRangeScan& scan, uint64_t ordinal) {
            const double t = mrpt::Clock::toDouble(scan.timestamp);
            const mrpt::poses::CPose3D extrinsic = settings.camera_pose.value_or(scan.sensorPose);
            const auto T = track->byIndex() ? track->cameraAtIndex(ordinal, extrinsic) : track->cameraAt(t, extrinsic);
            if (!T)
            {
                ++no_pose;  // never mapped with a stale pose
                return;
            }
            track->forgetBefore(t - PoseTrack::kKeptSeconds);  // a long recording's poses stay few
            camera_up.add(*T, upInCamera(extrinsic));
            pairer.pushScan(scan, *T, done);
        };
        const auto placeWaiting = [&](bool all) {
            while (!waiting.empty() &&
                   (all || waiting.size() > kMaxWaitingScans ||
                    (!track->empty() && mrpt::Clock::toDouble(waiting.front()->timestamp) <= track->endTime())))
            {
                placeScan(*waiting.front(), 0);  // poses in the stream: a track by time
                waiting.pop_front();
            }
        };
        for (size_t i = 0; source && i < source->size() && more(); ++i)
        {
            PairedFrame p;
            double t = 0;
            std::optional<Pose> own;
            source->load(i, p.frame, t, own);
            ++scans;
            if (!inTimeOrder(t)) continue;
            const mrpt::poses::CPose3D extrinsic = settings.camera_pose.value_or(mrpt::poses::CPose3D());
            const auto T = !track              ? own
                           : track->byIndex() ? track->cameraAtIndex(i, extrinsic)
                                              : track->cameraAt(t, extrinsic);
            if (!T)
            {
                ++no_pose;
                continue;
            }
            p.T_world_cam = *T;
            camera_up.add(*T, upInCamera(extrinsic));
            p.stamp = mrpt::Clock::fromDouble(t);
            p.labelled = p.frame.hasLabels();
            done.push_back(std::move(p));
            integrateDone();
            bar.update(done_share(double(i + 1) / double(source->size())), mapped);
        }
        // A label error names the sensor and stamp; the input file is said here (a rawlog's
        // objects are decoded ahead of mapping, so which object it was is not known here).
        try
        {
            while (stream && more())
            {
                auto& in = *stream;
                const auto obs = in.next();
                if (!obs) break;
                ++observations;
                if (settings.maps_rawlog_inputs && maps.rawlog()) maps.rawlog()->addInput(obs);
                if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(obs))
                {
                    if (!scan->hasRangeImage) continue;
                    if (!settings.rgbd_label.empty() && scan->sensorLabel != settings.rgbd_label)
                    {
                        ++other_sensor;
                        continue;
                    }
                    ++scans;
                    if (!inTimeOrder(mrpt::Clock::toDouble(scan->timestamp))) continue;
                    if (poses_in_stream)
                    {
                        waiting.push_back(scan);
                        placeWaiting(false);
                    }
                    else
                        placeScan(*scan, scans - 1);
                }
                else if (auto pose = std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(obs))
                {
                    if (poses_in_stream && track->addRobotPose(*pose)) placeWaiting(false);
                }
                else if (auto img = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(obs))
                    pairer.push(*img, mrpt::poses::CPose3D(), done);
                integrateDone();
                bar.update(done_share(in.progress()), mapped);
            }
            if (stream) placeWaiting(true);
            if (stream && observations == 0 && !stream->truncated())
                throw std::runtime_error(fmt::format("{}: the rawlog holds no observations (an empty file?)", input));
            if (poses_in_stream && track->empty() && !stream->truncated())
                throw std::runtime_error(fmt::format("{}: no CObservationRobotPose{} in the rawlog; give a pose file", input,
                                                     settings.pose_label.empty()
                                                         ? ""
                                                         : " labelled '" + settings.pose_label + "'"));
            pairer.flush(done);
            integrateDone();
        }
        catch (const InputError& e)
        {
            const std::string what = e.what();
            if (what.rfind(input, 0) == 0) throw;
            throw InputError(fmt::format("{}: {}", input, what));
        }
        bar.update(1.0, mapped);
        bar.finish();
        maps.finish();
        if (refinement)
        {
            fs::create_directories(out_dir);
            refinement->writeTum(out_dir + "/refined_poses.tum");
            fmt::print("pose refinement    : {}; poses in {}/refined_poses.tum\n", refinement->refiner().stats().summary(),
                       out_dir);
            fmt::print("time offset        : {}\n", refinement->timeOffset().summary());
        }

        // ---- what is in the final map
        const auto final_map = maps.current();
        if (!final_map)
        {
            if (stream && stream->truncated())
            {
                fmt::print(stderr, "pndt-map: {}\npndt-map: no frame before that point could be mapped\n",
                           stream->stopReason());
                return kExitTruncated;
            }
            throw std::runtime_error(fmt::format(
                "{}: no frame could be mapped ({} range scans, {} without a pose within {} s{}); the output folder "
                "holds no map of this run",
                input, scans, no_pose, settings.pose_max_gap,
                other_sensor > 0 ? fmt::format(", {} of sensors other than rgbd_label '{}'", other_sensor,
                                               settings.rgbd_label)
                                 : std::string()));
        }
        (void)track;
        fs::create_directories(out_dir);
        const PanopticMap& core = final_map->core();
        writeInstanceReport(core, out_dir + "/instances.json");
        writeRenderedViews(core, last->T_world_cam, last->frame.K, out_dir + "/view_last");
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
        for (const Voxel& v : core.voxels().voxels())
            if (core.isOccupied(v) && core.shapeOf(v).n > 0)
            {
                lo = lo.cwiseMin(core.shapeOf(v).meanVec());
                hi = hi.cwiseMax(core.shapeOf(v).meanVec());
            }
        const Eigen::Vector3d c = 0.5 * (lo + hi), ext = hi - lo;
        writeRenderedViews(core, lookAt(c + Eigen::Vector3d(0, -0.8 * ext.y(), 0.9 * ext.z() + 1.0), c),
                           overviewIntrinsics(), out_dir + "/view_overview");

        writeFloorPlan(core, out_dir + "/floor_plan.png");
        if (const auto note = camera_up.notZUpNote(
                "pndt-convert --level writes a rawlog in a world turned to z up; with --up when the cameras do not stand "
                "upright"))
            fmt::print(stderr, "pndt-map: note: {}\n", *note);
        if (!screenshot.empty()) writeScreenshot(*final_map, screenshot);
        if (!mesh_screenshot.empty()) writeMeshScreenshot(*final_map, mesh_screenshot);
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
        const FrameStats& st = maps.totals();
        const uint64_t labels_orphaned = pairer.labelImagesDropped() + pairer.labelImagesWaiting();
        fmt::print("\nframes mapped      : {} ({} with labels, {} geometry only)\n", mapped, labelled, mapped - labelled);
        fmt::print("frames skipped     : {} without a pose within {} s, {} of other sensors, {} stamped no later "
                   "than the frame before\n",
                   no_pose, settings.pose_max_gap, other_sensor, not_after);
        fmt::print("label images       : {} without a matching depth frame\n", labels_orphaned);
        fmt::print("pixels skipped     : {} invalid depth, {} beyond max range\n", st.skipped_invalid_depth,
                   st.skipped_over_range);
        fmt::print("maps written       : {} in {} (index.json{}); {:.2f} s of mapping time finalising (files are "
                   "written beside mapping)\n",
                   maps.index().size(), out_dir, keptMapsNote(maps), maps.secondsWriting());
        if (const MapRawlogWriter* r = maps.rawlog())
            fmt::print("maps.rawlog        : {} maps + {} input observations{}, {:.1f} MB written, {:.2f} s on its "
                       "writer thread\n",
                       r->mapsWritten(), r->inputsWritten(), rawlogFilesNote(*r), r->bytesWritten() / 1e6,
                       r->secondsWriting());
        fmt::print("final map          : {}\n", final_map->asString());
        fmt::print("memory             : map {:.1f} MB, peak RSS {:.1f} MB\n", core.memoryBytes() / 1e6,
                   peakRssBytes() / 1e6);
        fmt::print("time per stage (s) : projection {:.2f}, occupancy {:.2f}, matching {:.2f}, histograms {:.2f}\n",
                   st.seconds_projection, st.seconds_occupancy, st.seconds_matching, st.seconds_histograms);
        fmt::print("throughput         : {:.1f} frames/s overall ({:.2f} s), map updates {:.1f} frames/s\n",
                   mapped / wall, wall, st.secondsTotal() > 0 ? mapped / st.secondsTotal() : 0.0);
        fmt::print("outputs            : {}\n", outputsLine(settings.short_term, maps));
        if (view && !showInteractive(*final_map))
            fmt::print(stderr, "pndt-map: --view needs a display (DISPLAY is not set); use --screenshot\n");
        if (stream && stream->truncated())
        {
            fmt::print(stderr, "pndt-map: {}\npndt-map: mapped the {} frames before that point\n", stream->stopReason(),
                       mapped);
            return kExitTruncated;
        }
        if (g_stop)
        {
            fmt::print(stderr, "pndt-map: interrupted; the current map was finalised and written\n");
            return kExitInterrupted;
        }
    }
    catch (const io::WriteError& e)
    {
        fmt::print(stderr, "pndt-map: error: {}\n", e.what());
        if (fs::exists(fs::path(out_dir) / "index.json"))
            fmt::print(stderr, "pndt-map: mapping stopped; the maps listed in {}/index.json are complete\n", out_dir);
        return kExitWriteFailed;
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-map: error: {}\n", plainErrorText(e.what()));
        return kExitError;
    }
    return 0;
}
