// ShortTermMaps: one file per period, each equal to a map built from the same
// frames, a non-empty map at every moment, ids carried over by overlap.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <pndt/app/short_term_maps.h>
#include <pndt/mrpt/map_files.h>
#include <pndt/sim/renderer.h>
#include <pndt/sim/scene_builder.h>
#include <pndt/sim/trajectory.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

using namespace pndt;
using namespace pndt::app;
namespace fs = std::filesystem;

namespace
{
struct Frames
{
    std::vector<PanopticFrame> frames;
    std::vector<Pose> poses;
};

Frames roomFrames(int n)
{
    const sim::Scene scene = sim::makeTableWithChairsRoom();
    const CameraIntrinsics K{160, 120, 131.25, 131.25, 79.5, 59.5};
    Frames out;
    out.poses = sim::orbit({0, 0, 0}, 2.3, 1.5, 0.45, n);
    for (const Pose& T : out.poses)
    {
        out.frames.push_back(sim::renderPanopticFrame(scene, T, K));
    }
    return out;
}

fs::path tempDir()
{
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const fs::path d = fs::temp_directory_path() / ("pndt_stm_" + std::to_string(::getpid()) + info->name());
    fs::remove_all(d);
    return d;
}

/// Same keys, voxels and NDT surface records, byte for byte (all padding-free).
bool sameVoxels(const PanopticMap& a, const PanopticMap& b)
{
    return a.voxels().packedKeys() == b.voxels().packedKeys() &&
           std::memcmp(a.voxels().voxels().data(), b.voxels().voxels().data(), sizeof(Voxel) * a.voxels().size()) == 0 &&
           a.surfaceRecords().size() == b.surfaceRecords().size() &&
           std::memcmp(a.surfaceRecords().data(), b.surfaceRecords().data(),
                       sizeof(SurfaceRecord) * a.surfaceRecords().size()) == 0;
}
}  // namespace

TEST(ShortTermMaps, OneFilePerPeriodEachEqualToTheMapOfItsFrames)
{
    const Frames data = roomFrames(24);
    ShortTermOptions o;
    o.period = 6;  // frames
    o.period_in_frames = true;
    o.warmup = 0.5;
    o.stable_ids = false;  // so each file can be rebuilt independently, bit for bit
    o.out_dir = tempDir().string();
    ShortTermMaps maps([] { return PanopticNDTMap::Create(); }, o);
    for (size_t i = 0; i < data.frames.size(); ++i)
    {
        maps.integrate(data.frames[i], data.poses[i], double(i));
        ASSERT_TRUE(maps.current());
        EXPECT_FALSE(maps.current()->isEmpty()) << "consumer saw an empty map at frame " << i;
    }
    maps.finish();
    ASSERT_EQ(maps.index().size(), 4u);  // 24 frames / 6
    for (size_t k = 0; k < maps.index().size(); ++k)
    {
        const MapIndexEntry& e = maps.index()[k];
        const auto loaded = loadMapArchive((fs::path(o.out_dir) / e.file).string());
        // The same frames into a fresh map: frames [first, last] of that map.
        const size_t first = size_t(e.t_start), last = size_t(e.t_end);
        EXPECT_EQ(e.frames, last - first + 1);
        if (k > 0)
        {
            EXPECT_EQ(first, 6 * k - 3) << "warm-up starts half a period early";
        }
        PanopticNDTMap ref;
        for (size_t i = first; i <= last; ++i) ref.integrate(data.frames[i], data.poses[i]);
        EXPECT_TRUE(sameVoxels(loaded->core(), ref.core())) << e.file;
        EXPECT_EQ(loaded->core().instances().size(), e.instances);
    }
    EXPECT_TRUE(fs::exists(fs::path(o.out_dir) / "index.json"));
    fs::remove_all(o.out_dir);
}

TEST(ShortTermMaps, MapFilesOfAnEarlierRunInTheOutputFolderAreSaid)
{
    ShortTermOptions o;
    o.out_dir = tempDir().string();
    EXPECT_EQ(earlierRunNote(o), "");  // no folder yet
    fs::create_directories(o.out_dir);
    EXPECT_EQ(earlierRunNote(o), "");
    for (const char* f : {"map_0002.pndt.gz", "map_0000.pndt.gz", "map_0000.ply", "index.json", "notes.txt"})
        std::ofstream(fs::path(o.out_dir) / f) << "x";
    const std::string note = earlierRunNote(o);
    EXPECT_NE(note.find(o.out_dir + " holds 2 map file(s) (map_0000.pndt.gz .. map_0002.pndt.gz) of an earlier run"),
              std::string::npos)
        << note;
    // Its maps rawlogs too (a run cut into segments leaves an earlier single file beside them).
    for (const char* f : {"maps.rawlog", "maps-0001.rawlog", "maps-0000.rawlog", "maps-x.rawlog"})
        std::ofstream(fs::path(o.out_dir) / f) << "x";
    const std::string both = earlierRunNote(o);
    EXPECT_NE(both.find(" holds 2 map file(s) (map_0000.pndt.gz .. map_0002.pndt.gz) and 3 maps rawlog(s) (maps.rawlog "
                        ".. maps-0001.rawlog) of an earlier run"),
              std::string::npos)
        << both;
    o.prefix = "room";
    EXPECT_NE(earlierRunNote(o).find(" holds 3 maps rawlog(s)"), std::string::npos) << earlierRunNote(o);
    fs::remove(fs::path(o.out_dir) / "maps.rawlog");
    fs::remove(fs::path(o.out_dir) / "maps-0000.rawlog");
    fs::remove(fs::path(o.out_dir) / "maps-0001.rawlog");
    EXPECT_EQ(earlierRunNote(o), "");
    fs::remove_all(o.out_dir);
}

TEST(ShortTermMaps, AnInputOrRecordingThatIsTheRunsOwnMapsRawlogIsRefused)
{
    // Replaying <out>/maps.rawlog into <out> truncated the input before it was read (38 MB
    // -> 20 bytes, "the rawlog holds no observations"); a recording named so had two writers.
    ShortTermOptions o;
    o.out_dir = tempDir().string();
    o.write_rawlog = true;
    fs::create_directories(o.out_dir + "/sub");
    const std::string dir = o.out_dir;
    for (const std::string& own : {dir + "/maps.rawlog", dir + "/maps-0003.rawlog", dir + "/sub/../maps.rawlog",
                                   dir + "/./maps-12345.rawlog"})
        EXPECT_NE(ownOutputProblem(o, own).find("is this run's own maps rawlog"), std::string::npos) << own;
    for (const std::string& other : {dir + "/sub/maps.rawlog", dir + "/rec.rawlog", dir + "/maps-12.rawlog",
                                     dir + "/maps.rawlog.bak", dir + "/maps-0003.rawlog.gz"})
        EXPECT_EQ(ownOutputProblem(o, other), "") << other;
    // Through a link to the folder.
    const std::string link = dir + "-link";
    fs::remove(link);
    fs::create_directory_symlink(dir, link);
    EXPECT_NE(ownOutputProblem(o, link + "/maps.rawlog"), "");
    fs::remove(link);
    o.write_rawlog = false;  // --no-maps-rawlog: nothing of that name is written
    EXPECT_EQ(ownOutputProblem(o, dir + "/maps.rawlog"), "");
    fs::remove_all(o.out_dir);
}

TEST(ShortTermMaps, AFailedBackgroundWriteIsReportedNamingTheFile)
{
    const Frames data = roomFrames(12);
    ShortTermOptions o;
    o.period = 6;
    o.period_in_frames = true;
    o.out_dir = tempDir().string();
    ShortTermMaps maps([] { return PanopticNDTMap::Create(); }, o);
    // The output folder turns into a file: the first map's write fails on the writer thread.
    fs::remove_all(o.out_dir);
    std::ofstream(o.out_dir) << "in the way";
    for (size_t i = 0; i < data.frames.size(); ++i) maps.integrate(data.frames[i], data.poses[i], double(i));
    try
    {
        maps.finish();
        FAIL() << "expected the write error";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("map_0000.pndt.gz"), std::string::npos) << e.what();
    }
    fs::remove_all(o.out_dir);
}

TEST(ShortTermMaps, StableIdsAreCarriedToTheNextMap)
{
    const Frames data = roomFrames(24);
    ShortTermOptions o;
    o.period = 8;
    o.period_in_frames = true;
    o.warmup = 0.5;
    o.stable_ids = true;
    o.write_files = false;
    ShortTermMaps maps([] { return PanopticNDTMap::Create(); }, o);
    std::vector<std::vector<MapInstance>> per_map;
    PanopticNDTMap::Ptr seen;
    for (size_t i = 0; i < data.frames.size(); ++i)
    {
        maps.integrate(data.frames[i], data.poses[i], double(i));
        if (maps.current() != seen)
        {
            if (seen) per_map.push_back(seen->core().instances());
            seen = maps.current();
        }
    }
    maps.finish();
    per_map.push_back(seen->core().instances());
    ASSERT_EQ(per_map.size(), 3u);
    // Every chair/table instance centroid of map k+1 has an instance of map k with
    // the same id within 0.3 m.
    for (size_t k = 0; k + 1 < per_map.size(); ++k)
        for (const MapInstance& b : per_map[k + 1])
        {
            if (b.voxel_count < 20) continue;
            bool same = false;
            for (const MapInstance& a : per_map[k])
                same |= a.id == b.id && (a.centroid - b.centroid).norm() < 0.3;
            EXPECT_TRUE(same) << "map " << k + 1 << " instance " << b.id << " has no predecessor with its id";
        }
}

// Issue #23: a size budget for long runs. A map that reaches max_voxels is written early and
// the next map takes over with the next frame; no map grows past the budget by more than
// one frame's voxels, and none is empty.
TEST(ShortTermMaps, AVoxelBudgetWritesTheMapEarlyAndStartsANewOne)
{
    const Frames data = roomFrames(12);
    // Without a budget: one map for the run; its size after the first frame sets the budget.
    ShortTermOptions unbounded;
    unbounded.write_files = false;
    ShortTermMaps one([] { return PanopticNDTMap::Create(); }, unbounded);
    one.integrate(data.frames[0], data.poses[0], 0.0);
    const size_t first_frame_voxels = one.current()->core().voxels().size();
    for (size_t i = 1; i < data.frames.size(); ++i) one.integrate(data.frames[i], data.poses[i], double(i));
    one.finish();
    ASSERT_EQ(one.index().size(), 1u);
    const size_t budget = first_frame_voxels + first_frame_voxels / 4;
    ASSERT_GT(one.index()[0].voxels, budget);  // the budget matters on this input

    ShortTermOptions o;
    o.max_voxels = budget;
    o.out_dir = tempDir().string();
    ShortTermMaps maps([] { return PanopticNDTMap::Create(); }, o);
    for (size_t i = 0; i < data.frames.size(); ++i)
    {
        maps.integrate(data.frames[i], data.poses[i], double(i));
        ASSERT_TRUE(maps.current() != nullptr);
        // Never more than one frame past the budget.
        EXPECT_LE(maps.current()->core().voxels().size(), budget + first_frame_voxels) << "frame " << i;
    }
    maps.finish();
    EXPECT_GE(maps.budgetHandOvers(), 1u);
    EXPECT_EQ(maps.index().size(), maps.budgetHandOvers() + 1);
    uint64_t frames = 0;
    for (const MapIndexEntry& e : maps.index())
    {
        frames += e.frames;
        EXPECT_LE(e.voxels, budget + first_frame_voxels) << e.file;  // over by at most one frame
        EXPECT_GT(e.frames, 0u) << e.file;
        const auto loaded = loadMapArchive((fs::path(o.out_dir) / e.file).string());
        EXPECT_EQ(loaded->core().voxels().size(), e.voxels) << e.file;
    }
    EXPECT_EQ(frames, data.frames.size());  // every frame in exactly one map (no warm-up: period 0)
    fs::remove_all(o.out_dir);
}

// A robot mapping all day: keep_maps bounds the map files on disk and the length of index.json.
// The folder holds exactly the newest keep_maps archives and PLYs, the index lists exactly
// those, in order, and each loads as the map it was; fewer maps than that delete nothing.
TEST(ShortTermMaps, KeepMapsDeletesTheOldestFilesAndTheirIndexEntries)
{
    const Frames data = roomFrames(14);
    ShortTermOptions o;
    o.period = 2;  // frames: 7 maps
    o.period_in_frames = true;
    o.warmup = 0;
    o.keep_maps = 3;
    o.write_ply = true;
    o.out_dir = tempDir().string();
    const auto filesIn = [&](const std::string& ext) {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(o.out_dir))
            if (e.path().extension() == ext) names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    };
    const auto listed = [&] {
        std::ifstream in(fs::path(o.out_dir) / "index.json");
        std::vector<std::string> names;
        for (const auto& e : nlohmann::json::parse(in)) names.push_back(e.at("file").get<std::string>());
        return names;
    };
    {
        ShortTermMaps few([] { return PanopticNDTMap::Create(); }, o);
        for (size_t i = 0; i < 6; ++i) few.integrate(data.frames[i], data.poses[i], double(i));
        few.finish();
        EXPECT_EQ(few.index().size(), 3u);
        EXPECT_EQ(few.firstListedMap(), 0u);
        EXPECT_EQ(keptMapsNote(few), "");
        EXPECT_EQ(listed().size(), 3u);
        EXPECT_EQ(filesIn(".gz").size(), 3u);
    }
    fs::remove_all(o.out_dir);
    ShortTermMaps run([] { return PanopticNDTMap::Create(); }, o);
    for (size_t i = 0; i < data.frames.size(); ++i) run.integrate(data.frames[i], data.poses[i], double(i));
    run.finish();
    ASSERT_EQ(run.index().size(), 7u);
    EXPECT_EQ(run.firstListedMap(), 4u);
    EXPECT_EQ(keptMapsNote(run), " lists the newest 3; the 4 older deleted");
    const std::vector<std::string> expected = {"map_0004.pndt.gz", "map_0005.pndt.gz", "map_0006.pndt.gz"};
    EXPECT_EQ(listed(), expected);
    EXPECT_EQ(filesIn(".gz"), expected);
    EXPECT_EQ(filesIn(".ply"), (std::vector<std::string>{"map_0004.ply", "map_0005.ply", "map_0006.ply"}));
    for (size_t k = 4; k < 7; ++k)
    {
        const auto loaded = loadMapArchive((fs::path(o.out_dir) / run.index()[k].file).string());
        EXPECT_EQ(loaded->core().voxels().size(), run.index()[k].voxels) << run.index()[k].file;
    }
    fs::remove_all(o.out_dir);
}
