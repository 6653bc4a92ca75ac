// maps.rawlog (issue #21): the writer keeps time order when interleaving input
// observations, a truncated file (a crash) reads back its complete objects with
// MRPT's own reader and rawlog-edit, ShortTermMaps appends one observation per
// map, pndt-map's output is listed and cut by the stock rawlog-edit, and a full
// disk is reported as a write error naming the file; long runs cut the stream into
// files of N maps and delete the files whose maps all fell out of the newest kept.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>
#include <nlohmann/json.hpp>
#include <pndt/app/map_rawlog.h>
#include <pndt/app/short_term_maps.h>
#include <pndt/io/atomic_file.h>
#include <pndt/mrpt/CObservationPanopticMap.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <thread>

#include "cli_fixture.h"

using namespace pndt;
using namespace pndt::app;
namespace fs = std::filesystem;

namespace
{
/// What MRPT's reader gets out of a rawlog: every complete object, in order.
std::vector<mrpt::obs::CObservation::Ptr> readAll(const std::string& file)
{
    std::vector<mrpt::obs::CObservation::Ptr> out;
    mrpt::io::CFileGZInputStream f(file);
    auto a = mrpt::serialization::archiveFrom(f);
    for (;;)
    {
        try
        {
            mrpt::serialization::CSerializable::Ptr o;
            a >> o;
            out.push_back(std::dynamic_pointer_cast<mrpt::obs::CObservation>(o));
        }
        catch (...)  // end of the file, or the cut-off object
        {
            break;
        }
    }
    return out;
}

mrpt::obs::CObservation::Ptr poseAt(double t)
{
    auto p = mrpt::obs::CObservationRobotPose::Create();
    p->sensorLabel = "GT_POSE";
    p->timestamp = mrpt::Clock::fromDouble(t);
    p->pose.mean = mrpt::poses::CPose3D(t, 0, 0, 0, 0, 0);
    return p;
}

/// A map of the first `frames` frames of the room orbit.
PanopticNDTMap::Ptr smallMap(int frames)
{
    const cli::Room room(frames);
    std::mt19937 rng(1);
    auto m = PanopticNDTMap::Create();
    for (int i = 0; i < frames; ++i) m->integrate(room.frame(i, rng), room.poses[size_t(i)]);
    m->flushPending();
    m->core().finalize();
    return m;
}

void waitWritten(const MapRawlogWriter& w, uint64_t n)
{
    for (int i = 0; i < 2000 && w.mapsWritten() + w.inputsWritten() < n; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ASSERT_EQ(w.mapsWritten() + w.inputsWritten(), n);
}

std::string pluginArg() { return std::string(" -p ") + PNDT_PLUGIN_PATH; }
}  // namespace

TEST(MapRawlog, InterleavedInputsAndMapsAreInTimeOrder)
{
    const fs::path dir = cli::tempDir("rawlog_order");
    const std::string file = (dir / "maps.rawlog").string();
    const auto m1 = smallMap(2), m2 = smallMap(3);
    {
        MapRawlogWriter w({file, "MY_MAPS"});
        // Mapping lags the reading: inputs up to t=4 are read before the frame at 2
        // is mapped; map 0 (last frame 2) is handed over when frame 3 arrives.
        for (int i = 0; i <= 4; ++i) w.addInput(poseAt(i));
        w.mappedUpTo(2);
        w.addMap(m1, 0, 2, 3, 0);
        w.mappedUpTo(3);
        for (int i = 5; i <= 7; ++i) w.addInput(poseAt(i));
        w.addMap(m2, 3, 6, 4, 1);  // hand-over: releases the inputs up to 6 first
        w.finish();
        EXPECT_EQ(w.mapsWritten(), 2u);
        EXPECT_EQ(w.inputsWritten(), 8u);
        EXPECT_EQ(uint64_t(fs::file_size(file)), w.bytesWritten());
    }
    const auto objs = readAll(file);
    ASSERT_EQ(objs.size(), 10u);
    std::vector<std::string> order;
    double last = -1;
    for (const auto& o : objs)
    {
        const double t = mrpt::Clock::toDouble(o->timestamp);
        EXPECT_GE(t, last);
        last = t;
        const auto map = std::dynamic_pointer_cast<CObservationPanopticMap>(o);
        order.push_back(map ? "M" + std::to_string(map->sequence) : std::to_string(int(t)));
        if (map)
        {
            EXPECT_EQ(map->sensorLabel, "MY_MAPS");
        }
    }
    EXPECT_EQ(order, (std::vector<std::string>{"0", "1", "2", "M0", "3", "4", "5", "6", "M1", "7"}));
    const auto back = std::dynamic_pointer_cast<CObservationPanopticMap>(objs[8]);
    EXPECT_EQ(back->map->core().voxels().size(), m2->core().voxels().size());
    EXPECT_EQ(back->map->core().instances().size(), m2->core().instances().size());
    EXPECT_EQ(back->frames, 4u);
    EXPECT_DOUBLE_EQ(mrpt::Clock::toDouble(back->start), 3.0);
    fs::remove_all(dir);
}

TEST(MapRawlog, AFullDiskIsAWriteErrorNamingTheFile)
{
    // /dev/full fails every write with ENOSPC. MRPT's archive wraps what a stream
    // throws into its own exception, so the writer must hand back the sink's
    // WriteError itself (pndt-map exits 3 on a WriteError, 1 on anything else).
    if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
    MapRawlogWriter w({"/dev/full", "MY_MAPS"});
    w.addMap(smallMap(2), 0, 1, 2, 0);
    try
    {
        w.finish();
        FAIL() << "no error on a full disk";
    }
    catch (const io::WriteError& e)
    {
        EXPECT_NE(std::string(e.what()).find("cannot write /dev/full: No space left on device"), std::string::npos)
            << e.what();
        EXPECT_EQ(std::string(e.what()).find("MRPT exception"), std::string::npos) << e.what();
    }
    catch (const std::exception& e)
    {
        FAIL() << "not a WriteError: " << e.what();
    }
}

TEST(MapRawlog, ACrashLeavesAReadablePrefixOfCompleteObjects)
{
    const fs::path dir = cli::tempDir("rawlog_crash");
    const std::string file = (dir / "maps.rawlog").string();
    const auto m = smallMap(3);
    // Compressed size after each complete object (the writer flushes after each).
    std::vector<uint64_t> ends;
    std::vector<double> stamps;
    MapRawlogWriter w({file});
    for (int k = 0; k < 3; ++k)
    {
        w.addInput(poseAt(10.0 * k));
        w.mappedUpTo(10.0 * k);
        waitWritten(w, ends.size() + 1);
        ends.push_back(w.bytesWritten());
        stamps.push_back(10.0 * k);
        w.addMap(m, 10.0 * k, 10.0 * k + 5, 3, uint32_t(k));
        waitWritten(w, ends.size() + 1);
        ends.push_back(w.bytesWritten());
        stamps.push_back(10.0 * k + 5);
    }
    // The file as a crash would leave it: no gzip trailer, and cut at any byte.
    const std::string image = [&] {
        std::ifstream f(file, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    }();
    ASSERT_EQ(image.size(), ends.back());
    const auto truncated = [&](uint64_t bytes) {
        const std::string t = (dir / "cut.rawlog").string();
        std::ofstream(t, std::ios::binary).write(image.data(), std::streamsize(bytes));
        return t;
    };
    for (size_t k = 0; k < ends.size(); ++k)
    {
        const uint64_t before = k == 0 ? 0 : ends[k - 1];
        // Cut inside object k (its first byte, its middle): objects 0..k-1 read back.
        // (Not just short of its end: the last bytes are the flush marker, after the data.)
        for (const uint64_t cut : {before + 1, before + (ends[k] - before) / 2})
        {
            const auto objs = readAll(truncated(cut));
            ASSERT_EQ(objs.size(), k) << "cut at byte " << cut;
            for (size_t i = 0; i < k; ++i) EXPECT_DOUBLE_EQ(mrpt::Clock::toDouble(objs[i]->timestamp), stamps[i]);
        }
        // Cut right after it: k + 1 objects, the last a whole map when it is one.
        const auto objs = readAll(truncated(ends[k]));
        ASSERT_EQ(objs.size(), k + 1);
        if (const auto map = std::dynamic_pointer_cast<CObservationPanopticMap>(objs.back()))
        {
            EXPECT_EQ(map->map->core().voxels().size(), m->core().voxels().size());
        }
    }
    // The stock tool on a file cut inside the last map: 5 of the 6 objects.
    const std::string info = cli::run("rawlog-edit" + pluginArg() + " --info -i " +
                                      truncated(ends[4] + (ends[5] - ends[4]) / 2)).out;
    EXPECT_NE(info.find("Overall number of objects         : 5"), std::string::npos) << info;
    w.finish();
    EXPECT_EQ(readAll(file).size(), 6u);
    fs::remove_all(dir);
}

TEST(MapRawlog, ShortTermMapsAppendOneObservationPerMapStampedWithItsLastFrame)
{
    const fs::path dir = cli::tempDir("rawlog_stm");
    const cli::Room room(12);
    std::mt19937 rng(3);
    ShortTermOptions o;
    o.period = 4;
    o.period_in_frames = true;
    o.out_dir = dir.string();
    o.write_rawlog = true;
    {
        ShortTermMaps maps([] { return PanopticNDTMap::Create(); }, o);
        for (int i = 0; i < 12; ++i) maps.integrate(room.frame(i, rng), room.poses[size_t(i)], cli::stampOf(i));
        maps.finish();
        const auto objs = readAll((dir / "maps.rawlog").string());
        ASSERT_EQ(objs.size(), maps.index().size());
        ASSERT_EQ(objs.size(), 3u);
        for (size_t k = 0; k < objs.size(); ++k)
        {
            const auto m = std::dynamic_pointer_cast<CObservationPanopticMap>(objs[k]);
            ASSERT_TRUE(m && m->map);
            const MapIndexEntry& e = maps.index()[k];
            EXPECT_EQ(m->sensorLabel, "PANOPTIC_MAP");
            EXPECT_DOUBLE_EQ(mrpt::Clock::toDouble(m->timestamp), e.t_end);
            EXPECT_DOUBLE_EQ(mrpt::Clock::toDouble(m->start), e.t_start);
            EXPECT_EQ(m->frames, e.frames);
            EXPECT_EQ(m->sequence, k);
            EXPECT_EQ(m->map->core().voxels().size(), e.voxels);
            EXPECT_EQ(m->map->core().instances().size(), e.instances);
        }
    }
    fs::remove_all(dir);
}

TEST(MapRawlog, PndtMapOutputIsListedAndCutByTheStockRawlogEdit)
{
    const fs::path dir = cli::tempDir("rawlog_cli");
    const std::string input = (dir / "room.rawlog").string();
    cli::Room(24).writeRawlog(input, 24);  // 3 s at 8 frames/s from t = 1000
    const fs::path out = dir / "out";
    // Maps every second, interleaved with the input observations.
    auto r = cli::run(cli::mapExe() + input + " -o " + out.string() + " --period 1 --rawlog-inputs");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("maps.rawlog        : 3 maps + "), std::string::npos) << r.out;
    std::ifstream jf(out / "index.json");
    const auto index = nlohmann::json::parse(jf);
    ASSERT_EQ(index.size(), 3u);

    const std::string txt = (dir / "ts.txt").string();
    r = cli::run("rawlog-edit" + pluginArg() + " --list-timestamps -i " + (out / "maps.rawlog").string() +
                 " --text-file-output " + txt);
    std::ifstream f(txt);
    double t, last = 0;
    std::string label, cls;
    std::vector<double> map_stamps;
    size_t inputs = 0;
    while (f >> t >> label >> cls)
    {
        EXPECT_GE(t, last);  // one time line: --cut can stop at the first later object
        last = t;
        if (cls == "pndt::CObservationPanopticMap")
        {
            EXPECT_EQ(label, "PANOPTIC_MAP");
            map_stamps.push_back(t);
        }
        else
            ++inputs;
    }
    ASSERT_EQ(map_stamps.size(), 3u) << r.out;
    for (size_t k = 0; k < 3; ++k) EXPECT_NEAR(map_stamps[k], index[k]["t_end"].get<double>(), 1e-5);
    EXPECT_EQ(inputs, 24u * 4u);  // depth, two label images and a pose per frame

    // Cut the second map's second out of it: that map and its 8 frames' observations.
    const double from = index[0]["t_end"].get<double>() + 1e-3, to = index[1]["t_end"].get<double>() + 1e-3;
    const std::string cut = (dir / "cut.rawlog").string();
    r = cli::run(fmt::format("rawlog-edit{} --cut --from-time {:.4f} --to-time {:.4f} -i {} -o {}", pluginArg(),
                             from, to, (out / "maps.rawlog").string(), cut));
    const auto kept = readAll(cut);
    size_t maps = 0;
    for (const auto& o : kept)
    {
        const double s = mrpt::Clock::toDouble(o->timestamp);
        EXPECT_GE(s, from);
        EXPECT_LE(s, to);
        if (const auto m = std::dynamic_pointer_cast<CObservationPanopticMap>(o))
        {
            ++maps;
            EXPECT_EQ(m->sequence, 1u);
            EXPECT_EQ(m->map->core().voxels().size(), index[1]["voxels"].get<size_t>());
        }
    }
    EXPECT_EQ(maps, 1u) << r.out;
    EXPECT_EQ(kept.size(), 1u + 8u * 4u) << r.out;

    // Off: no maps.rawlog.
    r = cli::run(cli::mapExe() + input + " -o " + (dir / "off").string() + " --period 1 --no-maps-rawlog");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_FALSE(fs::exists(dir / "off" / "maps.rawlog"));
    fs::remove_all(dir);
}

namespace
{
/// "M<sequence>" for a map, the input's whole-second stamp otherwise.
std::vector<std::string> contentsOf(const std::string& file)
{
    std::vector<std::string> out;
    for (const auto& o : readAll(file))
    {
        const auto map = std::dynamic_pointer_cast<CObservationPanopticMap>(o);
        out.push_back(map ? "M" + std::to_string(map->sequence) : std::to_string(int(mrpt::Clock::toDouble(o->timestamp))));
    }
    return out;
}

std::vector<std::string> rawlogsIn(const fs::path& dir)
{
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".rawlog") files.push_back(e.path().filename());
    std::sort(files.begin(), files.end());
    return files;
}
}  // namespace

TEST(MapRawlog, SegmentsHoldNMapsEachAndTheInputsAfterAFilesLastMapGoToTheNext)
{
    const fs::path dir = cli::tempDir("rawlog_segments");
    const auto m = smallMap(2);
    MapRawlogOptions o;
    o.path = (dir / "maps.rawlog").string();
    o.segment_maps = 2;
    {
        MapRawlogWriter w(o);
        // Map k covers [2k, 2k + 1]; one input a second, released as mapping passes it.
        for (uint32_t k = 0; k < 5; ++k)
        {
            w.addInput(poseAt(2 * k));
            w.addInput(poseAt(2 * k + 1));
            w.addMap(m, 2 * k, 2 * k + 1, 2, k);
        }
        w.addInput(poseAt(10));
        w.finish();
        EXPECT_EQ(w.mapsWritten(), 5u);
        EXPECT_EQ(w.inputsWritten(), 11u);
        EXPECT_EQ(w.filesWritten(), 3u);
        EXPECT_EQ(w.filesDeleted(), 0u);
        uint64_t on_disk = 0;
        for (const auto& f : rawlogsIn(dir)) on_disk += fs::file_size(dir / f);
        EXPECT_EQ(on_disk, w.bytesWritten());
        EXPECT_EQ(rawlogFilesNote(w), " in maps-0000.rawlog .. maps-0002.rawlog");
    }
    EXPECT_EQ(rawlogsIn(dir), (std::vector<std::string>{"maps-0000.rawlog", "maps-0001.rawlog", "maps-0002.rawlog"}));
    EXPECT_EQ(contentsOf((dir / "maps-0000.rawlog").string()),
              (std::vector<std::string>{"0", "1", "M0", "2", "3", "M1"}));
    EXPECT_EQ(contentsOf((dir / "maps-0001.rawlog").string()),
              (std::vector<std::string>{"4", "5", "M2", "6", "7", "M3"}));
    EXPECT_EQ(contentsOf((dir / "maps-0002.rawlog").string()), (std::vector<std::string>{"8", "9", "M4", "10"}));
    fs::remove_all(dir);
}

TEST(MapRawlog, KeepMapsDeletesTheFilesWhoseMapsAreAllOlder)
{
    const fs::path dir = cli::tempDir("rawlog_keep");
    const auto m = smallMap(2);
    MapRawlogOptions o;
    o.path = (dir / "maps.rawlog").string();
    o.segment_maps = 2;
    o.keep_maps = 3;
    MapRawlogWriter w(o);
    // Files of maps {0,1} {2,3} {4,5} {6}: after map 6 the newest three are 4-6, so the
    // first two files go, the third stays (it holds map 4) with the open fourth.
    std::vector<std::vector<std::string>> after;  // files on disk after each map
    for (uint32_t k = 0; k < 7; ++k)
    {
        w.addMap(m, k, k + 0.5, 2, k);
        waitWritten(w, k + 1);
        after.push_back(rawlogsIn(dir));
    }
    w.finish();
    EXPECT_EQ(w.filesDeleted(), 2u);
    EXPECT_EQ(rawlogFilesNote(w), " in maps-0002.rawlog .. maps-0003.rawlog; the 2 older files deleted");
    using V = std::vector<std::string>;
    EXPECT_EQ(after[2], (V{"maps-0000.rawlog", "maps-0001.rawlog"}));  // maps 0-2 are the newest three
    EXPECT_EQ(after[3], (V{"maps-0000.rawlog", "maps-0001.rawlog"}));  // map 0 is out; 1 is still in the file
    EXPECT_EQ(after[4], (V{"maps-0001.rawlog", "maps-0002.rawlog"}));  // 0 and 1 out: the first file goes
    EXPECT_EQ(after[6], (V{"maps-0002.rawlog", "maps-0003.rawlog"}));
    EXPECT_EQ(contentsOf((dir / "maps-0002.rawlog").string()), (V{"M4", "M5"}));
    EXPECT_EQ(contentsOf((dir / "maps-0003.rawlog").string()), (V{"M6"}));
    // One file cannot drop its oldest maps.
    o.segment_maps = 0;
    EXPECT_THROW(MapRawlogWriter{o}, std::invalid_argument);
    fs::remove_all(dir);
}

TEST(MapRawlog, PndtMapWithKeepMapsLeavesTheNewestMapsInRawlogsTheStockToolsRead)
{
    const fs::path dir = cli::tempDir("rawlog_cli_keep");
    const std::string input = (dir / "room.rawlog").string();
    cli::Room(48).writeRawlog(input, 48);  // 6 s at 8 frames/s
    const fs::path out = dir / "out";
    auto r = cli::run(cli::mapExe() + input + " -o " + out.string() + " --period 1 --keep-maps 2");
    ASSERT_EQ(r.code, 0) << r.out;
    std::ifstream jf(out / "index.json");
    const auto index = nlohmann::json::parse(jf);
    ASSERT_EQ(index.size(), 2u);
    // Six maps in files of two (the automatic segment: keep_maps): maps 4 and 5 are kept.
    EXPECT_NE(r.out.find("maps.rawlog        : 6 maps + 0 input observations in maps-0002.rawlog; the 2 older "
                         "files deleted"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(rawlogsIn(out), (std::vector<std::string>{"maps-0002.rawlog"}));
    const std::string txt = (dir / "ts.txt").string();
    r = cli::run("rawlog-edit" + pluginArg() + " --list-timestamps -i " + (out / "maps-0002.rawlog").string() +
                 " --text-file-output " + txt);
    ASSERT_EQ(r.code, 0) << r.out;
    std::ifstream f(txt);
    double t;
    std::string label, cls;
    std::vector<double> stamps;
    while (f >> t >> label >> cls) stamps.push_back(t);
    ASSERT_EQ(stamps.size(), 2u) << r.out;
    for (size_t k = 0; k < 2; ++k) EXPECT_NEAR(stamps[k], index[k]["t_end"].get<double>(), 1e-5);

    // An explicit segment size without keep_maps keeps every file.
    r = cli::run(cli::mapExe() + input + " -o " + (dir / "seg").string() + " --period 1 --maps-rawlog-segment 4");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(rawlogsIn(dir / "seg"), (std::vector<std::string>{"maps-0000.rawlog", "maps-0001.rawlog"}));
    EXPECT_EQ(contentsOf((dir / "seg" / "maps-0001.rawlog").string()), (std::vector<std::string>{"M4", "M5"}));
    r = cli::run(cli::mapExe() + input + " -o " + (dir / "bad").string() + " --maps-rawlog-segment -1");
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.out.find("must be 0 or more"), std::string::npos) << r.out;
    fs::remove_all(dir);
}

TEST(MapRawlog, PndtMapKilledMidRunLeavesAReadableMapsRawlog)
{
    const fs::path dir = cli::tempDir("rawlog_kill");
    const std::string input = (dir / "room.rawlog").string();
    cli::Room(120).writeRawlog(input, 120);  // 15 s at 8 frames/s
    const fs::path out = dir / "out";
    const fs::path pid_file = dir / "pid";
    // Maps every 0.5 s (4 frames); killed (SIGKILL) once index.json lists 3 maps.
    ASSERT_EQ(std::system((cli::mapExe() + input + " -o " + out.string() + " --period 0.5 >" + (dir / "log").string() +
                           " 2>&1 & echo $! >" + pid_file.string())
                              .c_str()),
              0);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    pid_t pid = 0;
    std::ifstream(pid_file) >> pid;
    ASSERT_GT(pid, 0);
    bool killed = false;
    for (int i = 0; i < 3000 && !killed; ++i)
    {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        std::ifstream jf(out / "index.json");
        if (!jf) continue;
        try
        {
            if (nlohmann::json::parse(jf).size() >= 3) killed = ::kill(pid, SIGKILL) == 0;
        }
        catch (...)
        {
        }
    }
    if (!killed) GTEST_SKIP() << "pndt-map finished before it could be killed";
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    // Every object MRPT reads back is a whole map, in order, equal to its map_NNNN file's size.
    const auto objs = readAll((out / "maps.rawlog").string());
    ASSERT_GE(objs.size(), 1u);
    std::ifstream jf(out / "index.json");
    const auto index = nlohmann::json::parse(jf);
    double last = 0;
    for (size_t k = 0; k < objs.size(); ++k)
    {
        const auto m = std::dynamic_pointer_cast<CObservationPanopticMap>(objs[k]);
        ASSERT_TRUE(m && m->map);
        EXPECT_EQ(m->sequence, k);
        EXPECT_GT(mrpt::Clock::toDouble(m->timestamp), last);
        last = mrpt::Clock::toDouble(m->timestamp);
        if (k < index.size())
        {
            EXPECT_EQ(m->map->core().voxels().size(), index[k]["voxels"].get<size_t>());
        }
    }
    // And the stock tool agrees.
    const std::string info = cli::run("rawlog-edit" + pluginArg() + " --info -i " + (out / "maps.rawlog").string()).out;
    EXPECT_NE(info.find(fmt::format("Overall number of objects         : {}", objs.size())), std::string::npos) << info;
    fs::remove_all(dir);
}
