// pndt-live: RGB-D from an OpenNI2 camera + poses streamed by a localiser (RTAB-Map, ...) ->
// rolling short-term panoptic maps at camera rate, as pndt-map builds them from a rawlog
// (issue #19; README "Live with a camera").
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <pndt/app/cli_numbers.h>
#include <pndt/app/error_text.h>
#include <pndt/app/layered_config.h>
#include <pndt/app/map_config.h>
#include <pndt/app/map_outputs.h>
#include <pndt/app/map_rawlog.h>
#include <pndt/app/pose_refinement.h>
#include <pndt/class_set.h>
#include <pndt/io/atomic_file.h>
#include <pndt/live/live_pipeline.h>
#include <pndt/live/mrpt_capture.h>
#include <pndt/mrpt/config_section.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "heap_trim.h"
#include "mapper_settings.h"
#include "refine_cli.h"
#include "short_term_cli.h"

using namespace pndt;
using namespace pndt::app;
using namespace pndt::live;

namespace
{
std::atomic<bool> g_stop{false};
extern "C" void onSignal(int) { g_stop = true; }

/// Exit codes: 0 ok (also after Ctrl-C / SIGTERM: the map was finalised and written),
/// 1 error, 3 an output could not be written, 4 the camera was lost (unplugged, no frames):
/// the map holds what was mapped before and was written.
constexpr int kExitError = 1, kExitWriteFailed = 3, kExitCameraLost = 4;

}  // namespace

namespace
{
int runLive(int argc, char** argv)
{
    const int heap_arenas = capHeapArenas();  // before any thread starts
    CLI::App app{"pndt-live: an OpenNI2 RGB-D camera + streamed poses -> short-term panoptic NDT maps"};
    bool list_devices = false, no_registration = false, no_color = false;
    OniCaptureOptions cam;
    std::string intrinsics, out_dir = "out/live", model, up, record, pose_format = "rtabmap11", pose_frame,
                                  pose_file, stamps, capture_backend, mrpt_config;
    int pose_tcp = -1, pose_udp = -1;
    double label_wait = 0.25;
    double clock_offset = 0, pose_wait = 0.5, seconds = 0, period = -1, voxel_size = 0, grab_timeout = 3.0;
    uint64_t max_frames = 0;
    std::vector<std::string> presets, configs, sets;
    app.add_flag("--list-devices", list_devices, "list the OpenNI2 devices and exit");
    app.add_option("--capture", capture_backend, "capture backend: openni2 (OpenNI2's own API, device stamps; the "
                                                 "default) or mrpt (MRPT's COpenNI2Sensor, host stamps); config "
                                                 "[pndt-live] capture")
        ->check(CLI::IsMember({"openni2", "mrpt"}));
    app.add_option("--mrpt-config", mrpt_config, "--capture mrpt: INI[:SECTION] with COpenNI2Sensor keys (calibration "
                                                 "SECTION_LEFT/_RIGHT/_LEFT2RIGHT_POSE; SECTION defaults to OPENNI2); "
                                                 "config [pndt-live] mrpt_config");
    app.add_option("-d,--device", cam.device, "device index, serial number or OpenNI2 URI (default: the first)");
    app.add_option("--width", cam.width)->capture_default_str();
    app.add_option("--height", cam.height)->capture_default_str();
    app.add_option("--fps", cam.fps)->capture_default_str();
    app.add_flag("--no-registration", no_registration, "do not ask the device to register depth to colour");
    app.add_flag("--no-color", no_color, "depth only (geometry-only maps unless the model takes depth)");
    app.add_option("--intrinsics", intrinsics, "'fx fy cx cy' of the (registered) depth image; default: from the "
                                               "device's fields of view");
    app.add_option("--pose-tcp", pose_tcp, "listen for pose lines on this TCP port (one connection per localiser; "
                                           "reconnects welcome)");
    app.add_option("--pose-udp", pose_udp, "receive pose lines as UDP datagrams on this port");
    app.add_option("--pose-file", pose_file, "follow a pose file being appended to (tail -f)");
    std::string pose_grabber;
    app.add_option("--pose-grabber", pose_grabber, "INI:SECTION of an MRPT grabber (rawlog-grabber style) whose "
                                                   "CObservationRobotPose observations are the poses");
    app.add_option("--pose-format", pose_format, "pose lines: rtabmap11 (RTAB-Map's default export), rtabmap10, tum")
        ->capture_default_str();
    app.add_option("--pose-frame", pose_frame, "robot | camera (default: robot for rtabmap*, camera for tum)");
    app.add_option("--clock-offset", clock_offset, "seconds added to pose stamps (localiser clock -> frame clock)");
    app.add_option("--pose-wait", pose_wait, "seconds a frame waits (from its capture) for a pose at or after its "
                                             "stamp, then it is skipped and counted")
        ->capture_default_str()
        ->check(app::kNonNegative);
    app.add_option("--stamps", stamps, "frame clock: device (the camera's frame stamps; openni2 default) or host "
                                       "(time of grab; the only one --capture mrpt has)")
        ->check(CLI::IsMember({"device", "host"}));
    app.add_option("--grab-timeout", grab_timeout, "seconds without a frame after which the camera counts as lost")
        ->capture_default_str()
        ->check(app::kPositive);
    app.add_option("--label-wait", label_wait, "seconds the mapper waits for a frame's labels before mapping it "
                                               "geometry-only")
        ->capture_default_str()
        ->check(app::kNonNegative);
    app.add_option("--model", model, "segmentation model description (JSON); without it the map is geometry-only");
    app.add_option("--up", up, "gravity up in the poses' world frame, 'x y z' (segmentation)");
    app.add_option("--record", record, "write what was seen (depth, colour, labels, poses) as a rawlog; "
                                       "`pndt-map RECORD` rebuilds the same maps");
    double record_minutes = 0;
    size_t record_keep = 0;
    app.add_option("--record-minutes", record_minutes,
                   "cut the recording into files of this many minutes of sensor time (REC.rawlog -> REC-0000.rawlog, "
                   "REC-0001.rawlog, ...; `pndt-map REC-*.rawlog` replays them in order)")
        ->check(app::kPositive);
    app.add_option("--record-keep", record_keep,
                   "keep only the newest N files of the recording, deleting older ones (a black box of the last N x "
                   "--record-minutes minutes)")
        ->check(app::kPositive);
    app.add_option("--max-frames", max_frames, "stop after this many captured frames (0 = until Ctrl-C)");
    app.add_option("--seconds", seconds, "stop after this many seconds (0 = until Ctrl-C)")->check(app::kNonNegative);
    app.add_option("-o,--out", out_dir, "output folder (as pndt-map)")->capture_default_str();
    app.add_option("-p,--preset", presets, "preset from config/presets (as pndt-map)")
        ->delimiter(',')
        ->check(CLI::IsMember({"scannet", "hypersim", "realworld", "paper", "detector"}));
    app.add_option("-c,--config", configs, ".ini files layered over the defaults (repeatable)");
    app.add_option("-s,--set", sets, "override: section.key=value (repeatable)");
    // Given values go to the config (as pndt-map): out of range is an error, never "not given".
    CLI::Option* period_opt = app.add_option("--period", period, "short-term map period (config period_unit; 0 = one map)")
                                  ->check(app::kNonNegative);
    CLI::Option* voxel_opt = app.add_option("--voxel-size", voxel_size, "voxel size in metres")->check(app::kPositive);
    bool no_maps_rawlog = false, rawlog_inputs = false;
    app.add_flag("--no-maps-rawlog", no_maps_rawlog, "do not write maps.rawlog (config maps_rawlog; as pndt-map)");
    app.add_flag("--rawlog-inputs", rawlog_inputs,
                 "interleave the recorded observations with the maps in maps.rawlog (config maps_rawlog_inputs)");
    ShortTermCli short_term_cli;  // as pndt-map's
    short_term_cli.addTo(app);
    RefineCli refine_cli;  // as pndt-map's
    refine_cli.addTo(app);
    CLI11_PARSE(app, argc, argv);
    // CLI11's number checks let NaN through.
    for (const double v : {clock_offset, pose_wait, seconds, period, voxel_size, grab_timeout, label_wait, record_minutes})
        if (!std::isfinite(v))
        {
            fmt::print(stderr, "pndt-live: error: every number option takes a finite number, not {}\n", v);
            return kExitError;
        }
    if ((record_minutes > 0 || record_keep > 0) && record.empty())
    {
        fmt::print(stderr, "pndt-live: error: --record-minutes and --record-keep need --record\n");
        return kExitError;
    }
    if (record_keep > 0 && record_minutes <= 0)
    {
        fmt::print(stderr, "pndt-live: error: --record-keep needs --record-minutes (the files it keeps)\n");
        return kExitError;
    }
    // The recording as messages name it: "rec-NNNN.rawlog" once it is cut into files.
    const std::filesystem::path record_path(record);
    const std::string record_name =
        record_minutes > 0
            ? (record_path.parent_path() / (record_path.stem().string() + "-NNNN" + record_path.extension().string()))
                  .string()
            : record;
    // A recording never overwrites an earlier one (after a crash it may be all there is of it).
    if (!record.empty() && record_minutes <= 0 && std::filesystem::exists(record))
    {
        fmt::print(stderr, "pndt-live: error: {} is there from an earlier recording; give another --record name or "
                           "move it\n",
                   record);
        return kExitError;
    }
    if (record_minutes > 0)
        if (const auto earlier = numberedRawlogsOf(record); !earlier.empty())
        {
            fmt::print(stderr, "pndt-live: error: {} is there from an earlier recording ({} files); give another "
                               "--record name or move them\n",
                       earlier.front(), earlier.size());
            return kExitError;
        }

    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    // What an output error leaves behind: nothing before these are set.
    bool maps_started = false, recording_started = false;
    try
    {
        if (list_devices)
        {
            const auto devices = listOniDevices();
            if (devices.empty()) fmt::print("no OpenNI2 device found\n");
            for (size_t i = 0; i < devices.size(); ++i)
                fmt::print("{}: {}  {} {}  serial {}  usb {:04x}:{:04x}\n", i, devices[i].uri, devices[i].vendor,
                           devices[i].name, devices[i].serial.empty() ? "-" : devices[i].serial,
                           devices[i].usb_vendor, devices[i].usb_product);
            return 0;
        }
        // ---- configuration: exactly pndt-map's
        const std::string config = configDir(PNDT_CONFIG_DIR);
        std::vector<std::string> files = {config + "/panoptic_ndt.ini", config + "/pndt_map.ini"};
        for (const auto& preset : presets) files.push_back(config + "/presets/" + preset + ".ini");
        files.insert(files.end(), configs.begin(), configs.end());
        if (period_opt->count()) sets.push_back(fmt::format("pndt-map.period={}", period));
        if (voxel_opt->count()) sets.push_back(fmt::format("MAP_PanopticNDTMap_00_creationOpts.voxel_size={}", voxel_size));
        if (no_maps_rawlog) sets.push_back("pndt-map.maps_rawlog=false");
        short_term_cli.addSetsTo(sets);
        if (rawlog_inputs) sets.push_back("pndt-map.maps_rawlog_inputs=true");
        const auto cfg = loadLayeredConfig(files, sets);
        rejectUnknownSections(cfg, {"pndt-map", "pndt-live", "MAP"}, {"MAP_"});
        MapperSettings settings = MapperSettings::load(cfg);
        {
            // [pndt-live]: what only the live app has; the command line wins.
            ConfigSection live(cfg, "pndt-live");
            std::string c_capture = "openni2", c_mrpt;
            live.read("capture", c_capture);
            live.read("mrpt_config", c_mrpt);
            live.rejectUnknownKeys();
            if (capture_backend.empty()) capture_backend = c_capture;
            if (mrpt_config.empty()) mrpt_config = c_mrpt;
            if (capture_backend != "openni2" && capture_backend != "mrpt")
                throw std::runtime_error("config [pndt-live] capture = '" + capture_backend + "': openni2 or mrpt");
        }
        const bool use_mrpt = capture_backend == "mrpt";
        if (use_mrpt && stamps == "device")
            throw std::runtime_error("--capture mrpt: MRPT's COpenNI2Sensor stamps frames with the host clock when it "
                                     "reads them (the device stamp is not passed on): use --stamps host or "
                                     "--capture openni2");
        if (!use_mrpt && !mrpt_config.empty())
            throw std::runtime_error("--mrpt-config is for --capture mrpt");
        if (stamps.empty()) stamps = use_mrpt ? "host" : "device";
        settings.short_term.out_dir = out_dir;
        if (!record.empty())  // two writers on one file lost the recording (exit 0)
            if (const std::string problem = ownOutputProblem(settings.short_term, record); !problem.empty())
                throw std::runtime_error("--record: " + problem);
        const auto factory = mapFactory(cfg);
        const auto prototype = factory();

        // ---- segmentation (checked before the camera opens: a bad model fails at once)
        const ClassSet classes = ClassSet::nyuv2_40();
        std::unique_ptr<seg::Segmenter> segmenter;
        if (!model.empty())
        {
            seg::SegmenterOptions so;
            if (!up.empty())
            {
                std::istringstream in(up);
                Eigen::Vector3d u;
                if (!(in >> u.x() >> u.y() >> u.z()) || !u.allFinite() || u.norm() < 1e-9)
                    throw std::runtime_error("--up '" + up + "' is not 'x y z' (finite, not all zero)");
                so.up_world = u.normalized();
            }
            segmenter = seg::loadSegmenter(model, classes, so);
        }

        // ---- poses
        // [pndt-map]'s pose keys as pndt-map reads them, where the command line does not say.
        if (!app.count("--pose-format")) pose_format = settings.pose_format;
        if (!app.count("--pose-frame")) pose_frame = settings.pose_frame;
        if (pose_file.empty() && settings.pose_source == "file") pose_file = settings.pose_file;
        if (pose_tcp < 0 && pose_udp < 0 && pose_file.empty() && pose_grabber.empty())
            throw std::runtime_error(
                "no pose source: give --pose-tcp PORT, --pose-udp PORT, --pose-file FILE or --pose-grabber INI:SECTION");
        const LineFormat lf = parseLineFormat(pose_format);
        const PoseFrame pf = !pose_frame.empty()         ? parsePoseFrame(pose_frame)
                             : lf == LineFormat::Tum     ? PoseFrame::Camera
                                                         : PoseFrame::Robot;
        // --clock-offset, else [pndt-map] clock_offset (as pndt-map)
        LivePoseBuffer poses("LIVE_POSE", app.count("--clock-offset") ? clock_offset : settings.clock_offset);
        std::vector<std::unique_ptr<PoseSource>> sources;
        if (pose_tcp >= 0)
        {
            int bound = 0;
            sources.push_back(tcpPoseServer(pose_tcp, lf, pf, poses, &bound));
        }
        if (pose_udp >= 0) sources.push_back(udpPoseReceiver(pose_udp, lf, pf, poses));
        if (!pose_file.empty()) sources.push_back(tailPoseFile(pose_file, lf, pf, poses));
        if (!pose_grabber.empty())
        {
            const auto colon = pose_grabber.rfind(':');
            if (colon == std::string::npos) throw std::runtime_error("--pose-grabber '" + pose_grabber + "' is not INI:SECTION");
            sources.push_back(mrptGrabberPoses(pose_grabber.substr(0, colon), pose_grabber.substr(colon + 1), poses));
        }

        // ---- camera
        cam.registration = !no_registration;
        cam.color = !no_color;
        if (!intrinsics.empty())
        {
            std::istringstream in(intrinsics);
            CameraIntrinsics K{cam.width, cam.height, 0, 0, 0, 0};
            if (!(in >> K.fx >> K.fy >> K.cx >> K.cy)) throw std::runtime_error("--intrinsics '" + intrinsics + "' is not 'fx fy cx cy'");
            cam.K = K;
        }
        std::optional<OniCapture> oni;
        std::optional<MrptCapture> mrpt_capture;
        std::unique_ptr<FrameGrabber> oni_grabber;
        FrameGrabber* grabber = nullptr;
        std::string camera_text;
        if (use_mrpt)
        {
            MrptCaptureOptions mo;
            mo.camera = cam;
            if (const auto colon = mrpt_config.rfind(':'); colon != std::string::npos)
            {
                mo.ini = mrpt_config.substr(0, colon);
                mo.section = mrpt_config.substr(colon + 1);
            }
            else
                mo.ini = mrpt_config;
            grabber = &mrpt_capture.emplace(mo);
            camera_text = mrpt_capture->describe();
        }
        else
        {
            oni.emplace(cam);
            oni_grabber = grabberOf(*oni);
            grabber = oni_grabber.get();
            camera_text = oni->describe() + (stamps == "device" ? "" : "; frames stamped with the host clock at grab");
        }
        std::optional<FramePoseRefinement> refinement = refine_cli.make(settings);  // as pndt-map --refine (issue #22)

        io::ensureDirectory(out_dir);
        if (const auto folder = std::filesystem::path(record).parent_path(); !record.empty() && !folder.empty())
            io::ensureDirectory(folder.string());  // before any output: nothing is left if it cannot be
        if (const std::string note = earlierRunNote(settings.short_term); !note.empty())
            fmt::print(stderr, "pndt-live: note: {}\n", note);
        ShortTermMaps maps(factory, settings.short_term);
        maps_started = true;
        LiveOptions lo;
        lo.pose_wait = pose_wait;
        // MRPT's own stamp is the host clock at its read: taken as the frame's stamp.
        lo.device_stamps = use_mrpt || stamps == "device";
        lo.rawlog_inputs = settings.maps_rawlog_inputs;
        lo.refinement = refinement ? &*refinement : nullptr;
        lo.max_pose_gap = settings.pose_max_gap;
        lo.camera_pose = settings.camera_pose.value_or(mrpt::poses::CPose3D());
        lo.max_frames = max_frames;
        lo.record = record;
        lo.record_minutes = record_minutes;
        lo.record_keep = record_keep;
        lo.grab_timeout = grab_timeout;
        lo.label_wait = label_wait;
        LivePipeline pipeline(*grabber, segmenter.get(), poses, maps, prototype->insertionOptions, lo);
        recording_started = !record.empty();

        fmt::print("pndt-live: {}\n", camera_text);
        fmt::print("poses     : ");
        for (const auto& s : sources) fmt::print("{}; ", s->describe());
        fmt::print("{} lines, {} frame\n", pose_format, pf == PoseFrame::Camera ? "camera" : "robot");
        fmt::print("labels    : {}\n", segmenter ? segmenter->describe() : "none (geometry only, no --model)");
        fmt::print("map       : {}; outputs in {}{}\n", prototype->asString(), out_dir,
                   record.empty() ? "" : "; recording " + record_name);
        std::fflush(stdout);

        const auto t0 = std::chrono::steady_clock::now();
        uint64_t last_cap = 0, last_seg = 0, last_map = 0;
        double last_t = 0, next_trim = 10;
        HeapTrim trim;
        pipeline.run(g_stop, [&](const LiveStats& s, double t) {
            const double dt = std::max(1e-3, t - last_t);
            fmt::print("[{:6.1f} s] capture {:5.1f} fps | segmentation {:5.1f} fps, labelled {:3.0f}%, dropped {} | "
                       "mapping {:5.1f} fps | pose waits {} skipped, no pose {} | poses {} ({} connected)\n",
                       t, (s.captured - last_cap) / dt, (s.segmented - last_seg) / dt,
                       s.captured ? 100.0 * s.labelled / s.captured : 0.0, s.seg_dropped + s.label_late,
                       (s.mapped - last_map) / dt,
                       s.pose_wait_skipped, s.no_pose_skipped, poses.received(), poses.open_connections.load());
            std::fflush(stdout);
            last_cap = s.captured, last_seg = s.segmented, last_map = s.mapped, last_t = t;
            if (t >= next_trim)
            {
                next_trim = t + 10;
                trim.run();
            }
            if (seconds > 0 && t >= seconds) g_stop = true;
        });
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        sources.clear();

        const LiveStats& s = pipeline.stats();
        fmt::print("\nframes captured    : {} in {:.1f} s ({:.1f} fps)\n", s.captured, wall, s.captured / wall);
        fmt::print("frames mapped      : {} ({:.1f} fps; {} labelled = {:.0f}% of captured, the rest geometry only)\n",
                   s.mapped, s.mapped / wall, s.labelled, s.captured ? 100.0 * s.labelled / s.captured : 0.0);
        fmt::print("frames skipped     : {} waited {:.2f} s for a pose in vain, {} without a pose within {} s, {} "
                   "dropped because mapping was behind, {} dropped with a stamp not after the frame before\n",
                   s.pose_wait_skipped, pose_wait, s.no_pose_skipped, settings.pose_max_gap, s.mapping_dropped,
                   s.stamp_back_dropped);
        fmt::print("segmentation       : {} frames labelled, {} went on unlabelled (segmentation behind), {} labels "
                   "too late for the mapper (> {} s), {} errors\n",
                   s.labelled, s.seg_dropped, s.label_late, label_wait, s.seg_errors);
        fmt::print("poses              : {} received, {} out of order dropped, {} bad lines, {} connections\n",
                   poses.received(), poses.droppedOutOfOrder(), poses.bad_lines.load(), poses.connections.load());
        fmt::print("maps written       : {} in {} (index.json{})\n", maps.index().size(), out_dir,
                   keptMapsNote(maps));
        fmt::print("heap               : {}, freed memory handed back {} times, {:.2f} ms at most\n",
                   heap_arenas == 1 ? "one malloc arena" : "malloc arenas as MALLOC_ARENA_MAX says", trim.runs,
                   trim.longest_ms);
        if (!record.empty())
        {
            const auto name = [&](uint64_t k) {
                return std::filesystem::path(numberedRawlogPath(record, k)).filename().string();
            };
            const uint64_t files = s.recorded_files, deleted = s.recorded_files_deleted;
            const std::string where =
                record_minutes <= 0 ? record
                : files - deleted == 1
                    ? numberedRawlogPath(record, deleted)
                    : fmt::format("{} .. {}", numberedRawlogPath(record, deleted), name(files - 1));
            fmt::print("recording          : {} ({} frames, {:.1f} MB{})\n", where, s.recorded_frames,
                       s.recorded_bytes / 1e6,
                       deleted ? fmt::format("; the {} older files deleted", deleted) : std::string());
        }
        if (const MapRawlogWriter* r = maps.rawlog())
            fmt::print("maps.rawlog        : {} maps + {} input observations{}, {:.1f} MB written\n",
                       r->mapsWritten(), r->inputsWritten(), rawlogFilesNote(*r), r->bytesWritten() / 1e6);
        if (refinement)
        {
            refinement->writeTum(out_dir + "/refined_poses.tum");
            fmt::print("pose refinement    : {}; poses in {}/refined_poses.tum\n",
                       refinement->refiner().stats().summary(), out_dir);
            fmt::print("time offset        : {}\n", refinement->timeOffset().summary());
        }
        if (mrpt_capture && mrpt_capture->replaced())
            fmt::print("capture            : {} frames replaced by newer ones before the pipeline took them\n",
                       mrpt_capture->replaced());
        if (const auto m = maps.current())
        {
            const PanopticMap& core = m->core();
            writeInstanceReport(core, out_dir + "/instances.json");
            if (pipeline.last()) writeRenderedViews(core, pipeline.last()->T_world_cam, pipeline.last()->frame.K,
                                                    out_dir + "/view_last");
            writeFloorPlan(core, out_dir + "/floor_plan.png");
            if (const auto note = pipeline.cameraUp().notZUpNote(
                    "the localiser's world is taken as it comes: have it publish poses in a z-up world"))
                fmt::print(stderr, "pndt-live: note: {}\n", *note);
            fmt::print("final map          : {}\n", m->asString());
        }
        else
            fmt::print(stderr, "pndt-live: no frame was mapped (no poses for the frames?): no map written\n");
        const bool map_written = maps.current() != nullptr;
        if (s.camera_lost)
        {
            fmt::print(stderr, "pndt-live: camera lost: {} after {} frames; {} (exit code {})\n", s.camera_error,
                       s.captured,
                       map_written ? "the map holds what was mapped before and was written" : "no frame was mapped",
                       kExitCameraLost);
            return kExitCameraLost;
        }
        if (g_stop)
            fmt::print("pndt-live: stopped; {}\n",
                       map_written ? "the current map was finalised and written" : "no frame was mapped, no map written");
    }
    catch (const io::WriteError& e)
    {
        fmt::print(stderr, "pndt-live: error: {}\n", e.what());
        if (maps_started && std::filesystem::exists(std::filesystem::path(out_dir) / "index.json"))
            fmt::print(stderr, "pndt-live: mapping stopped; the maps listed in {}/index.json are complete\n", out_dir);
        if (recording_started)
            fmt::print(stderr, "pndt-live: the recording {} holds what was written before the error (pndt-map replays "
                               "its complete frames)\n", record_name);
        return kExitWriteFailed;
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-live: error: {}\n", plainErrorText(e.what()));
        return kExitError;
    }
    return 0;
}
}  // namespace

int main(int argc, char** argv)
{
    const int rc = runLive(argc, argv);
    // A grab thread left blocked inside MRPT / OpenNI2 (a hung camera): the outputs are
    // written, and OpenNI2's exit-time shutdown would close the device under that thread
    // (ThreadSanitizer reported the race): leave without running the exit handlers.
    if (pndt::live::MrptCapture::abandoned())
    {
        std::fflush(stdout);
        std::fflush(stderr);
        std::_Exit(rc);
    }
    return rc;
}
