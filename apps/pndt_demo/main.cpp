// pndt-demo: maps a generated synthetic room (table with chairs) through the real
// MRPT path — CMultiMetricMap built from an .ini, fed CObservation3DRangeScan and
// the two float32 panoptic label images per frame — then writes the map archive,
// a PLY, an instance report and PNG views.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <mrpt/config/CConfigFile.h>
#include <pndt/app/map_config.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <pndt/app/map_outputs.h>
#include <pndt/mrpt/map_files.h>
#include <pndt/mrpt/observation_frame.h>
#include <pndt/mrpt/rawlog_frames.h>
#include <pndt/sim/renderer.h>
#include <pndt/sim/scene_builder.h>
#include <pndt/sim/trajectory.h>

#include <chrono>
#include <filesystem>
#include <random>


using namespace pndt;

int main(int argc, char** argv)
{
    CLI::App app{"PanopticNDT demo: map a generated room and write the results"};
    std::string out_dir = "out/demo";
    // Found as pndt-map finds it: $PNDT_CONFIG_DIR, the installed copy, else the source tree's.
    std::string config = pndt::app::configDir(PNDT_CONFIG_DIR) + "/panoptic_ndt.ini";
    int frames = 36, width = 640, height = 480;
    unsigned seed = 1;
    std::string rawlog;
    app.add_option("-o,--out", out_dir, "output folder")->capture_default_str();
    app.add_option("-c,--config", config, ".ini with a [MAP] section for CMultiMetricMap")->capture_default_str();
    app.add_option("-n,--frames", frames, "frames along the orbit")->capture_default_str()->check(CLI::Range(1, 100000));
    app.add_option("--width", width, "image width")->capture_default_str()->check(CLI::Range(16, 8192));
    app.add_option("--height", height, "image height")->capture_default_str()->check(CLI::Range(16, 8192));
    app.add_option("--seed", seed, "seed of the per-frame instance id permutation")->capture_default_str();
    app.add_option("--rawlog", rawlog, "also write the frames as a rawlog (scan + label images + GT_POSE)");
    CLI11_PARSE(app, argc, argv);

    try
    {
        if (!std::filesystem::exists(config)) throw std::runtime_error(config + ": no such config file");
        mrpt::config::CConfigFile cfg(config);
        mrpt::maps::TSetOfMetricMapInitializers inits;
        inits.loadFromConfigFile(cfg, "MAP");
        mrpt::maps::CMultiMetricMap maps;
        maps.setListOfMaps(inits);
        auto map = maps.mapByClass<PanopticNDTMap>();
        if (!map) throw std::runtime_error(config + ": [MAP] defines no PanopticNDTMap (PanopticNDTMap_count=1)");
        std::filesystem::create_directories(out_dir);

        const sim::Scene scene = sim::makeTableWithChairsRoom();
        const double s = width / 640.0;
        const CameraIntrinsics K{width, height, 525.0 * s, 525.0 * s, (width - 1) / 2.0, (height - 1) / 2.0};
        const auto trajectory = sim::orbit({0, 0, 0}, 2.3, 1.5, 0.45, frames);
        std::mt19937 rng(seed);
        std::uniform_int_distribution<uint32_t> random_id(100, 100000);

        fmt::print("pndt-demo: {} frames {}x{}, {}\n", frames, width, height, map->asString());
        fmt::print("{:>5} {:>8} {:>7} {:>7} {:>5} {:>5} {:>8}\n", "frame", "valid_px", "hit_vx", "voxels", "new",
                   "match", "ms");
        std::unique_ptr<RawlogFrameWriter> writer;
        if (!rawlog.empty()) writer = std::make_unique<RawlogFrameWriter>(rawlog);
        sim::RenderedFrame r;
        const auto t_start = std::chrono::steady_clock::now();
        for (int i = 0; i < frames; ++i)
        {
            sim::render(scene, trajectory[size_t(i)], K, r);
            // Perfect labels, but instance ids permuted every frame as a network's are.
            PanopticFrame f;
            f.K = K;
            f.depth = r.depth;
            f.semantic = r.semantic;
            f.semantic_score.resize(width, height, 0.95f);
            f.instance = r.instance;
            std::vector<uint32_t> perm(64, 0);
            for (auto& p : perm) p = random_id(rng);
            for (auto& z : f.instance.data) z = z ? perm[z % perm.size()] : 0;
            f.panoptic_score.resize(width, height, 0.9f);

            const auto stamp = mrpt::Clock::fromDouble(1.7e9 + i / 30.0);
            auto scan = mrpt::obs::CObservation3DRangeScan::Create();
            scan->sensorLabel = "RGBD";
            scan->timestamp = stamp;
            rangeScanFrom(f, *scan);
            auto sem = mrpt::obs::CObservationImage::Create();
            auto inst = mrpt::obs::CObservationImage::Create();
            labelImagesFrom(f, "RGBD", stamp, *sem, *inst);
            const mrpt::poses::CPose3D robot = mrptSensorPoseOf(trajectory[size_t(i)]);

            if (writer) writer->write(f, 1.7e9 + i / 30.0, trajectory[size_t(i)]);
            const FrameStats before = map->insertionStats().totals;
            maps.insertObservation(*scan, robot);
            maps.insertObservation(*sem, robot);
            maps.insertObservation(*inst, robot);
            const FrameStats& now = map->insertionStats().totals;
            fmt::print("{:>5} {:>8} {:>7} {:>7} {:>5} {:>5} {:>8.1f}\n", i, now.valid_pixels - before.valid_pixels,
                       now.hit_voxels - before.hit_voxels, map->core().voxels().size(),
                       now.new_instances - before.new_instances, now.matched_instances - before.matched_instances,
                       1000.0 * (now.secondsTotal() - before.secondsTotal()));
        }
        map->flushPending();
        if (writer) writer->commit();
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
        const FrameStats& tot = map->insertionStats().totals;

        map->core().finalize();
        const std::string archive = out_dir + "/map.pndt.gz", ply = out_dir + "/map.ply";
        saveArchive(*map, archive);
        writePly(*map, ply);
        app::writeInstanceReport(map->core(), out_dir + "/instances.json");
        const Pose overview = sim::lookAt({0.0, -2.6, 2.4}, {0.0, 0.0, 0.4});
        app::writeRenderedViews(map->core(), overview, K, out_dir + "/view");

        fmt::print("\nmapped {} frames ({} with labels, {} geometry only) in {:.2f} s: {:.1f} frames/s "
                   "(map update {:.1f} frames/s; rendering the input is the rest)\n",
                   frames, map->insertionStats().frames_with_labels, map->insertionStats().frames_geometry_only,
                   wall, frames / wall, frames / tot.secondsTotal());
        fmt::print("stage seconds: projection {:.3f}, occupancy {:.3f}, matching {:.3f}, histograms {:.3f}\n",
                   tot.seconds_projection, tot.seconds_occupancy, tot.seconds_matching, tot.seconds_histograms);
        fmt::print("{}\nmemory {:.1f} MB\n", map->asString(), map->core().memoryBytes() / 1e6);
        for (const MapInstance& mi : map->core().instances())
            fmt::print("  instance {:>4}: {:<10} {:>5} voxels, centroid ({:+.2f}, {:+.2f}, {:+.2f})\n", mi.id,
                       map->core().options().classes.name(mi.semantic), mi.voxel_count, mi.centroid.x(),
                       mi.centroid.y(), mi.centroid.z());
        fmt::print("wrote {}, {}, {}/instances.json, {}/view_*.png\n", archive, ply, out_dir, out_dir);
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-demo: error: {}\n", e.what());
        return 1;
    }
    return 0;
}
