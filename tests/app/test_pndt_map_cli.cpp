// pndt-map end to end, as a user runs it: short-term maps, poses from a file,
// bad input, signals, and MRPT's own rawlog-edit on the outputs.
#include <gtest/gtest.h>
#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/serialization/CArchive.h>
#include <nlohmann/json.hpp>
#include <pndt/app/observation_stream.h>
#include <pndt/mrpt/map_files.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <set>
#include <tuple>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "cli_fixture.h"

using namespace cli;
using pndt::loadMapArchive;

namespace
{
nlohmann::json readJson(const fs::path& p)
{
    std::ifstream f(p);
    return nlohmann::json::parse(f);
}

/// Shared input: 40 frames (5 s) of the room with GT poses.
const fs::path& roomRawlog()
{
    static const fs::path p = [] {
        const fs::path d = tempDir("input");
        Room(40).writeRawlog((d / "room.rawlog").string(), 40);
        return d / "room.rawlog";
    }();
    return p;
}
}  // namespace

TEST(PndtMapCli, WritesOneMapPerPeriodThatLoadsBackAndReportsTheFurniture)
{
    const fs::path out = tempDir("periods");
    const RunResult r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " --period 1.25");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("frames mapped      : 40 (40 with labels, 0 geometry only)"), std::string::npos) << r.out;
    // 40 frames at 8/s span [1000, 1004.875]: periods of 1.25 s -> 4 maps.
    const auto index = readJson(out / "index.json");
    ASSERT_EQ(index.size(), 4u) << index.dump(1);
    uint64_t frames = 0;
    for (const auto& e : index)
    {
        const auto m = loadMapArchive((out / e["file"].get<std::string>()).string());
        EXPECT_EQ(m->core().voxels().size(), e["voxels"].get<size_t>());
        EXPECT_EQ(m->core().instances().size(), e["instances"].get<size_t>());
        EXPECT_TRUE(fs::exists(out / (e["file"].get<std::string>().substr(0, 8) + ".ply")));
        frames += e["frames"].get<uint64_t>();
    }
    EXPECT_GE(frames, 40u);  // warm-up frames feed two maps

    // One map of the whole input: its report lists the table and the four chairs
    // within one voxel of the truth, the centroid of each object's seen surface
    // (unique 1 cm voxels of all back-projected GT pixels, as the paper builds
    // its 3D ground truth).
    const RunResult full = run(mapExe() + roomRawlog().string() + " -o " + (out / "full").string());
    ASSERT_EQ(full.code, 0) << full.out;
    const Room room(40);
    std::map<uint32_t, std::set<std::tuple<int, int, int>>> cells;
    pndt::sim::RenderedFrame rf;
    for (int i = 0; i < 40; ++i)
    {
        pndt::sim::render(room.scene, room.poses[size_t(i)], room.K, rf);
        for (int row = 0; row < room.K.height; ++row)
            for (int col = 0; col < room.K.width; ++col)
                if (const uint32_t z = rf.instance.at(row, col))
                {
                    const Eigen::Vector3d p = room.poses[size_t(i)] * room.K.unproject(col, row, rf.depth.at(row, col));
                    cells[z].emplace(int(std::floor(p.x() * 100)), int(std::floor(p.y() * 100)),
                                     int(std::floor(p.z() * 100)));
                }
    }
    std::map<uint32_t, Eigen::Vector3d> truth;
    for (const auto& [z, set] : cells)
    {
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (const auto& [x, y, w] : set) c += Eigen::Vector3d(x + 0.5, y + 0.5, w + 0.5) / 100.0;
        truth[z] = c / double(set.size());
    }
    const auto report = readJson(out / "full" / "instances.json");
    ASSERT_TRUE(report["classes"].contains("chair")) << report.dump(1);
    ASSERT_TRUE(report["classes"].contains("table"));
    EXPECT_EQ(report["classes"]["chair"].size(), 4u) << report.dump(1);
    EXPECT_EQ(report["classes"]["table"].size(), 1u);
    for (const auto& [z, t] : truth)
    {
        const std::string cls = z == 1 ? "table" : "chair";
        double best = 1e9;
        for (const auto& inst : report["classes"][cls])
        {
            const Eigen::Vector3d c(inst["centroid"][0], inst["centroid"][1], inst["centroid"][2]);
            best = std::min(best, (c - t).norm());
        }
        std::printf("[measured] %s %u: centroid error %.3f m\n", cls.c_str(), z, best);
        EXPECT_LT(best, 0.10) << cls << " " << z << " truth " << t.transpose();
    }
    for (const char* v : {"view_last_panoptic.png", "view_last_panoptic_rgb8.png", "view_overview_semantic.png"})
        EXPECT_GT(fs::file_size(out / v), 100u) << v;
}
// The overview took the last frame's intrinsics: with the principal point off the image the
// look-at target projected off it, and every overview picture was empty (exit 0).
TEST(PndtMapCli, TheOverviewHasACameraOfItsOwnWhateverTheFramesIntrinsics)
{
    const fs::path out = tempDir("overview");
    Room room(8);
    room.K = pndt::CameraIntrinsics{160, 120, 131.25, 131.25, -100.0, 200.0};
    room.writeRawlog((out / "offc.rawlog").string(), 8);
    const RunResult r = run(mapExe() + (out / "offc.rawlog").string() + " -o " + (out / "m").string());
    ASSERT_EQ(r.code, 0) << r.out;
    const cv::Mat last = cv::imread((out / "m/view_last_depth.png").string(), cv::IMREAD_UNCHANGED);
    const cv::Mat over = cv::imread((out / "m/view_overview_depth.png").string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(last.empty());
    ASSERT_FALSE(over.empty());
    EXPECT_EQ(last.cols, 160);  // the camera's own view at its own size
    EXPECT_GT(cv::countNonZero(last), 0);
    EXPECT_EQ(over.cols, 640);
    EXPECT_EQ(over.rows, 480);
    EXPECT_GT(cv::countNonZero(over), 640 * 480 / 20) << "the overview shows the map";
}

// A world whose z is not up (Redwood's first camera) gave a floor plan that is a front view and
// a pndt-nav grid on a wall, without a word: said now, with what to do.
TEST(PndtMapCli, AWorldWhoseZIsNotUpIsSaid)
{
    const fs::path out = tempDir("not_z_up");
    RunResult r = run(mapExe() + roomRawlog().string() + " -o " + (out / "z_up").string());
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(r.out.find("points along world"), std::string::npos) << r.out;
    Room room(8);
    pndt::Pose turn = pndt::Pose::Identity();  // the room's +z becomes -y, as in a camera-centred y-down world
    turn.linear() << 1, 0, 0, 0, 0, -1, 0, 1, 0;
    for (pndt::Pose& p : room.poses) p = turn * p;
    room.writeRawlog((out / "y_down.rawlog").string(), 8);
    r = run(mapExe() + (out / "y_down.rawlog").string() + " -o " + (out / "y_down").string());
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("pndt-map: note: the poses' up (a robot's z, a camera's -y) points along world (0.00, -1.00, "
                         "0.00) on average"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("pndt-convert --level writes a rawlog in a world turned to z up"), std::string::npos) << r.out;
}

TEST(PndtMapCli, RtabmapFormat11PosesGiveTheSameMapAsRawlogPoses)
{
    const fs::path out = tempDir("rtabmap");
    Room(40).writeRtabmap11((out / "poses.txt").string(), 40);
    const RunResult a = run(mapExe() + roomRawlog().string() + " -o " + (out / "a").string());
    const RunResult b = run(mapExe() + roomRawlog().string() + " -o " + (out / "b").string() + " --poses " +
                            (out / "poses.txt").string() + " --pose-format rtabmap11");
    ASSERT_EQ(a.code, 0) << a.out;
    ASSERT_EQ(b.code, 0) << b.out;
    const auto ma = loadMapArchive((out / "a/map_0000.pndt.gz").string());
    const auto mb = loadMapArchive((out / "b/map_0000.pndt.gz").string());
    // The same poses, once as yaw/pitch/roll (rawlog) and once as quaternions
    // (file), differ by ~1e-16; the synthetic floor lies exactly on a voxel
    // boundary (z = 0), so a handful of floor samples may change voxel. All else
    // must agree.
    const auto& va = ma->core().voxels();
    const auto& vb = mb->core().voxels();
    EXPECT_NEAR(double(va.size()), double(vb.size()), 0.001 * va.size());
    size_t common = 0, same_label = 0, same_occ = 0;
    for (uint32_t i = 0; i < va.size(); ++i)
    {
        const uint32_t j = vb.find(va.key(i));
        if (j == pndt::kNoRecord) continue;
        ++common;
        same_occ += ma->core().isOccupied(va[i]) == mb->core().isOccupied(vb[j]);
        same_label += ma->core().panopticLabel(i) == mb->core().panopticLabel(j);
    }
    EXPECT_GE(common, size_t(0.999 * va.size()));
    EXPECT_GE(same_occ, size_t(0.999 * common));
    EXPECT_GE(same_label, size_t(0.999 * common));
    EXPECT_EQ(ma->core().instances().size(), mb->core().instances().size());
}

// A stampless pose file (KITTI) was matched by made-up stamps (line k at k / 30 s) against the
// rawlog's real ones: 39 of the room's 40 frames "without a pose". It goes by index now: frame
// k takes line k, the map that of the rawlog's own poses; frames past the file's end have none.
TEST(PndtMapCli, AStamplessPoseFileGoesByFrameIndex)
{
    const fs::path out = tempDir("kitti");
    const Room room(40);
    const auto writeKitti = [&](const fs::path& path, int n) {
        FILE* f = std::fopen(path.c_str(), "w");
        for (int i = 0; i < n; ++i)
        {
            const Eigen::Matrix4d M = room.poses[size_t(i)].matrix();
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 4; ++c) std::fprintf(f, "%.17g%s", M(r, c), r == 2 && c == 3 ? "\n" : " ");
        }
        std::fclose(f);
    };
    writeKitti(out / "all.kitti", 40);
    writeKitti(out / "first30.kitti", 30);
    const RunResult a = run(mapExe() + roomRawlog().string() + " -o " + (out / "a").string());
    const RunResult b = run(mapExe() + roomRawlog().string() + " -o " + (out / "b").string() + " --poses " +
                            (out / "all.kitti").string() + " --pose-format kitti");
    ASSERT_EQ(a.code, 0) << a.out;
    ASSERT_EQ(b.code, 0) << b.out;
    EXPECT_NE(b.out.find("frames mapped      : 40"), std::string::npos) << b.out;
    const auto ma = loadMapArchive((out / "a/map_0000.pndt.gz").string());
    const auto mb = loadMapArchive((out / "b/map_0000.pndt.gz").string());
    const auto& va = ma->core().voxels();
    const auto& vb = mb->core().voxels();
    size_t same_occ = 0, common = 0;
    for (uint32_t i = 0; i < va.size(); ++i)
        if (const uint32_t j = vb.find(va.key(i)); j != pndt::kNoRecord)
        {
            ++common;
            same_occ += ma->core().isOccupied(va[i]) == mb->core().isOccupied(vb[j]);
        }
    EXPECT_GE(common, size_t(0.999 * va.size()));  // the same poses (rounded to 17 digits)
    EXPECT_GE(same_occ, size_t(0.999 * common));
    const RunResult c = run(mapExe() + roomRawlog().string() + " -o " + (out / "c").string() + " --poses " +
                            (out / "first30.kitti").string() + " --pose-format kitti");
    ASSERT_EQ(c.code, 0) << c.out;
    EXPECT_NE(c.out.find("frames mapped      : 30"), std::string::npos) << c.out;
    EXPECT_NE(c.out.find("frames skipped     : 10 without a pose"), std::string::npos) << c.out;
}

TEST(PndtMapCli, AClockOffsetLinesUpPosesStampedOnAnotherClock)
{
    // The same poses stamped 0.25 s early (a localiser on another clock): with --clock-offset 0.25
    // (or [pndt-map] clock_offset) the map is the one of the right stamps, voxel for voxel.
    const fs::path out = tempDir("clock_offset");
    Room(40).writeRtabmap11((out / "poses.txt").string(), 40);
    {
        std::ifstream in(out / "poses.txt");
        std::ofstream early(out / "early.txt");
        for (std::string line; std::getline(in, line);)
        {
            if (line.empty() || line[0] == '#')
            {
                early << line << "\n";
                continue;
            }
            std::istringstream ls(line);
            std::string stamp, rest;
            ls >> stamp;
            std::getline(ls, rest);
            early << fmt::format("{:.6f}", std::stod(stamp) - 0.25) << rest << "\n";
        }
    }
    const std::string poses = " --pose-format rtabmap11 --poses ";
    const RunResult a = run(mapExe() + roomRawlog().string() + " -o " + (out / "a").string() + poses + (out / "poses.txt").string());
    const RunResult b = run(mapExe() + roomRawlog().string() + " -o " + (out / "b").string() + poses +
                            (out / "early.txt").string() + " --clock-offset 0.25");
    const RunResult c = run(mapExe() + roomRawlog().string() + " -o " + (out / "c").string() + poses +
                            (out / "early.txt").string() + " -s pndt-map.clock_offset=0.25");
    const RunResult d = run(mapExe() + roomRawlog().string() + " -o " + (out / "d").string() + poses + (out / "early.txt").string());
    ASSERT_EQ(a.code, 0) << a.out;
    ASSERT_EQ(b.code, 0) << b.out;
    ASSERT_EQ(c.code, 0) << c.out;
    ASSERT_EQ(d.code, 0) << d.out;
    const auto ma = loadMapArchive((out / "a/map_0000.pndt.gz").string());
    auto sameMap = [&](const fs::path& dir) {
        const auto mb = loadMapArchive((dir / "map_0000.pndt.gz").string());
        const auto& va = ma->core().voxels();
        const auto& vb = mb->core().voxels();
        if (va.size() != vb.size()) return false;
        for (uint32_t i = 0; i < va.size(); ++i)
        {
            const uint32_t j = vb.find(va.key(i));
            if (j == pndt::kNoRecord || ma->core().isOccupied(va[i]) != mb->core().isOccupied(vb[j]) ||
                !(ma->core().panopticLabel(i) == mb->core().panopticLabel(j)))
                return false;
        }
        return true;
    };
    EXPECT_TRUE(sameMap(out / "b"));
    EXPECT_TRUE(sameMap(out / "c"));
    EXPECT_FALSE(sameMap(out / "d"));  // without the offset the poses are 0.25 s late
}

TEST(PndtMapCli, TruncatedRawlogMapsWhatItCouldAndSaysWhere)
{
    const fs::path out = tempDir("truncated");
    const fs::path cut = out / "cut.rawlog";
    {
        std::ifstream in(roomRawlog(), std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), {});
        std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() * 6 / 10));
    }
    const RunResult r = run(mapExe() + cut.string() + " -o " + (out / "m").string());
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("truncated or corrupt at object #"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("cut.rawlog"), std::string::npos) << r.out;
    const auto m = loadMapArchive((out / "m/map_0000.pndt.gz").string());
    EXPECT_FALSE(m->isEmpty());
}

// A missing input is named, and nothing is left in the output folder (before, an empty
// maps.rawlog was: the outputs were opened before the input).
TEST(PndtMapCli, AMissingInputIsNamedAndLeavesNoOutput)
{
    const fs::path out = tempDir("missing");
    fs::create_directories(out / "empty_folder");  // a dataset folder without depth/
    for (const std::string& input : {(out / "none.rawlog").string(), (out / "empty_folder").string()})
    {
        const std::string args = input.find("folder") != std::string::npos ? " --input-format redwood" : "";
        const RunResult r = run(mapExe() + input + args + " -o " + (out / "m").string());
        EXPECT_EQ(r.code, 1) << r.out;
        EXPECT_NE(r.out.find(input), std::string::npos) << r.out;
        EXPECT_TRUE(!fs::exists(out / "m") || fs::is_empty(out / "m")) << input;
    }
    // An empty file is said as such (it was "no CObservationRobotPose in the rawlog; give a pose file").
    std::ofstream(out / "empty.rawlog").flush();
    const RunResult r = run(mapExe() + (out / "empty.rawlog").string() + " -o " + (out / "e").string());
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("empty.rawlog: the rawlog holds no observations (an empty file?)"), std::string::npos) << r.out;
    // An output path that is a file: no claim about an index.json there.
    std::ofstream(out / "a_file") << "x";
    const RunResult f = run(mapExe() + roomRawlog().string() + " -o " + (out / "a_file").string());
    EXPECT_NE(f.code, 0) << f.out;
    EXPECT_NE(f.out.find("a_file"), std::string::npos) << f.out;
    EXPECT_EQ(f.out.find("index.json are complete"), std::string::npos) << f.out;
}

TEST(PndtMapCli, PoseProblemsAreReportedOrCounted)
{
    const fs::path out = tempDir("poses");
    // Missing file.
    RunResult r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " --poses " +
                      (out / "nope.txt").string() + " --pose-format tum");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("nope.txt"), std::string::npos) << r.out;
    // Out of order.
    std::ofstream(out / "back.txt") << "1000.0 0 0 0 0 0 0 1\n1002.0 0 0 0 0 0 0 1\n1001.0 0 0 0 0 0 0 1\n";
    r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " --poses " + (out / "back.txt").string() +
            " --pose-format tum");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("back.txt"), std::string::npos) << r.out;
    // Poses for the first half only: the rest is skipped and counted, its labels orphaned.
    Room(40).writeRtabmap11((out / "all.txt").string(), 40);
    {
        std::ifstream in(out / "all.txt");
        std::ofstream half(out / "half.txt");
        std::string line;
        for (int i = 0; std::getline(in, line) && i <= 20; ++i) half << line << "\n";
    }
    r = run(mapExe() + roomRawlog().string() + " -o " + (out / "half").string() + " --poses " +
            (out / "half.txt").string() + " --pose-format rtabmap11");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("frames mapped      : 20 "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("frames skipped     : 20 without a pose"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("label images       : 40 without a matching depth frame"), std::string::npos) << r.out;
}

namespace
{
/// The room rawlog rewritten by `edit` (the observations in file order).
fs::path rewrittenRoom(const fs::path& path,
                       const std::function<void(std::vector<mrpt::obs::CObservation::Ptr>&)>& edit)
{
    std::vector<mrpt::obs::CObservation::Ptr> obs;
    pndt::app::ObservationStream in(roomRawlog().string());
    while (auto o = in.next()) obs.push_back(o);
    edit(obs);
    mrpt::io::CFileGZOutputStream out(path.string());
    auto ar = mrpt::serialization::archiveFrom(out);
    for (const auto& o : obs) ar << *o;
    return path;
}
bool isPose(const mrpt::obs::CObservation::Ptr& o)
{
    return std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(o) != nullptr;
}
std::string mapBytes(const fs::path& dir)
{
    const auto m = loadMapArchive((dir / "map_0000.pndt.gz").string());
    const auto keys = m->core().voxels().packedKeys();
    std::string b(reinterpret_cast<const char*>(keys.data()), keys.size() * sizeof(uint64_t));
    const auto& v = m->core().voxels().voxels();
    b.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(pndt::Voxel));
    return b;
}
}  // namespace

TEST(PndtMapCli, RawlogPosesAreTakenInOnePassWhereverTheyStand)
{
    const fs::path out = tempDir("stream_poses");
    RunResult r = run(mapExe() + roomRawlog().string() + " -o " + (out / "ref").string());
    ASSERT_EQ(r.code, 0) << r.out;
    // Every robot pose moved behind its frame's scan and label images: the scans
    // wait for it and get the same poses, so the map is the same.
    const fs::path late = rewrittenRoom(out / "late.rawlog", [](auto& obs) {
        for (size_t i = 0; i + 1 < obs.size();)
        {
            if (!isPose(obs[i])) { ++i; continue; }
            size_t j = i + 1;  // move it behind the non-pose observations that follow
            while (j < obs.size() && !isPose(obs[j])) ++j;
            std::rotate(obs.begin() + long(i), obs.begin() + long(i) + 1, obs.begin() + long(j));
            i = j;
        }
    });
    r = run(mapExe() + late.string() + " -o " + (out / "late").string());
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("frames mapped      : 40 "), std::string::npos) << r.out;
    EXPECT_EQ(mapBytes(out / "late"), mapBytes(out / "ref"));

    // Two poses swapped: an error naming the file, out of order.
    const fs::path swapped = rewrittenRoom(out / "swapped.rawlog", [](auto& obs) {
        std::vector<size_t> at;
        for (size_t i = 0; i < obs.size(); ++i)
            if (isPose(obs[i])) at.push_back(i);
        std::swap(obs[at[10]], obs[at[11]]);
    });
    r = run(mapExe() + swapped.string() + " -o " + (out / "swapped").string());
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("swapped.rawlog"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("out of order"), std::string::npos) << r.out;

    // No robot pose at all: an error that says to give a pose file.
    const fs::path none = rewrittenRoom(out / "none.rawlog", [](auto& obs) {
        obs.erase(std::remove_if(obs.begin(), obs.end(), isPose), obs.end());
    });
    r = run(mapExe() + none.string() + " -o " + (out / "none").string());
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("no CObservationRobotPose"), std::string::npos) << r.out;
}

TEST(PndtMapCli, UnknownConfigKeysAndSectionsAreErrorsNamingThem)
{
    const fs::path out = tempDir("config");
    RunResult r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " -s pndt-map.periode=3");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("'periode'"), std::string::npos) << r.out;
    r = run(mapExe() + roomRawlog().string() + " -o " + out.string() +
            " -s MAP_PanopticNDTMap_00_creationOpts.theta_q=0.3");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("'theta_q'"), std::string::npos) << r.out;
    r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " -s MAP_PanopticNDTMap_00_creatOpts.x=1");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("MAP_PanopticNDTMap_00_creatOpts"), std::string::npos) << r.out;
    r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " -s pndt-map.period=-1");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("'period'"), std::string::npos) << r.out;
    // [MAP]: MRPT reads only <map class>_count there; a typo or a map pndt-map never builds was
    // silently ignored.
    for (const auto& [set, message] : std::vector<std::pair<std::string, std::string>>{
             {"MAP.foo=1", "config [MAP]: unknown key 'foo'"},
             {"MAP.PanopticNDTMaps_count=1", "config [MAP]: unknown key 'PanopticNDTMaps_count'"},
             {"MAP.PanopticNDTMap_count=2", "config [MAP]: PanopticNDTMap_count=2: the apps build one PanopticNDTMap"},
             {"MAP.COccupancyGridMap2D_count=1", "config [MAP]: COccupancyGridMap2D_count=1: the apps build one"}})
    {
        r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " -s " + set);
        EXPECT_EQ(r.code, 1) << set << "\n" << r.out;
        EXPECT_NE(r.out.find(message), std::string::npos) << set << "\n" << r.out;
    }
    // A pose format without a pose file did nothing; an unknown one was taken until a file was read.
    r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " --pose-format kitti");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("--pose-format kitti is the format of a pose file: give --poses FILE"), std::string::npos)
        << r.out;
    r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " -s pndt-map.pose_format=kiti");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("kiti"), std::string::npos) << r.out;
    // The plugin's own errors come through MRPT: one line, without its exception banner.
    r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " -s MAP_PanopticNDTMap_00_creationOpts.ray_mode=foo");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("pndt-map: error: config section 'MAP_PanopticNDTMap_00_creationOpts', key 'ray_mode': 'foo' "
                         "is not one of merged, per_pixel"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(r.out.find("MRPT exception"), std::string::npos) << r.out;
    r = run(mapExe() + roomRawlog().string() + " -o " + out.string() +
            " --max-frames 2 -s MAP.COccupancyGridMap2D_count=0");
    EXPECT_EQ(r.code, 0) << r.out;  // zero of another map is no map
    // Options given with a value that is no value: errors, never "not given" (a negative or NaN
    // --voxel-size and --period were the defaults, --max-frames -1 all frames).
    for (const char* bad : {"--voxel-size -0.1", "--voxel-size 0", "--voxel-size nan", "--period -1", "--period nan",
                            "--max-frames -1"})
    {
        r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " " + bad);
        EXPECT_NE(r.code, 0) << bad << "\n" << r.out;
        EXPECT_EQ(r.out.find("frames mapped"), std::string::npos) << bad << "\n" << r.out;
        EXPECT_NE(r.out.find(std::string(bad).substr(2, 5)), std::string::npos) << bad << "\n" << r.out;
    }
}

TEST(PndtMapCli, MaxFramesMapsExactlyThatMany)
{
    // Frames completed together (labels after their depth frame, the pairer's flush) were all
    // mapped: --max-frames 3 mapped 4.
    const fs::path out = tempDir("max_frames");
    for (const int n : {1, 3, 5})
    {
        const RunResult r = run(mapExe() + roomRawlog().string() + " -o " + (out / std::to_string(n)).string() +
                                " --max-frames " + std::to_string(n));
        EXPECT_EQ(r.code, 0) << r.out;
        EXPECT_NE(r.out.find(fmt::format("frames mapped      : {} ", n)), std::string::npos) << r.out;
    }
    // The progress lines count towards --max-frames when it ends the run first: they stopped at
    // 40-60 % of the file's bytes on a finished run.
    const RunResult p = run(std::string(PNDT_MAP_EXE) + " " + roomRawlog().string() + " -o " + (out / "p").string() +
                            " --max-frames 5");
    EXPECT_EQ(p.code, 0) << p.out;
    std::istringstream lines(p.out);
    int last_percent = -1, last_frames = -1;
    for (std::string line; std::getline(lines, line);)
    {
        int percent = 0, frames = 0;
        if (std::sscanf(line.c_str(), "pndt-map %d%% %d frames", &percent, &frames) != 2) continue;
        EXPECT_GE(percent, 20 * frames) << line;  // at least the share of the 5 frames mapped
        last_percent = percent, last_frames = frames;
    }
    EXPECT_EQ(last_percent, 100) << p.out;
    EXPECT_EQ(last_frames, 5) << p.out;
    fs::remove_all(out);
}

TEST(PndtMapCli, RefinementFromTheConfigAsFromTheCommandLine)
{
    // [pndt-map] refine / refine_options give what --refine / --refine-option give, byte for byte.
    auto slurp = [](const fs::path& p) {
        std::ifstream f(p);
        return std::string(std::istreambuf_iterator<char>(f), {});
    };
    const fs::path cli = tempDir("refine_cli"), ini = tempDir("refine_ini");
    const std::string input = roomRawlog().string() + " --period 0 --max-frames 12 -o ";
    RunResult r = run(mapExe() + input + cli.string() + " --refine-option max_points=600 --refine-option thing_weight=0.3");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("time offset        : "), std::string::npos) << r.out;
    r = run(mapExe() + input + ini.string() + " -s pndt-map.refine=true -s 'pndt-map.refine_options=max_points=600 thing_weight=0.3'");
    ASSERT_EQ(r.code, 0) << r.out;
    const std::string poses = slurp(cli / "refined_poses.tum");
    EXPECT_EQ(std::count(poses.begin(), poses.end(), '\n'), 2 + 12) << poses;  // two comment lines, a pose per frame
    EXPECT_NE(poses.find("# camera / localiser time offset: not estimated"), std::string::npos) << poses;  // 12 frames
    EXPECT_EQ(poses, slurp(ini / "refined_poses.tum"));

    r = run(mapExe() + input + ini.string() + " -s 'pndt-map.refine_options=max_points=600 maxpoints=3'");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("key 'refine_options': 'maxpoints=3'"), std::string::npos) << r.out;

    // Tuned options kept beside refine = false: no refinement (they turned it on, 15-27 ms a frame).
    const fs::path off = tempDir("refine_off");
    r = run(mapExe() + input + off.string() + " -s pndt-map.refine=false -s 'pndt-map.refine_options=max_points=600'");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(r.out.find("pose refinement"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(off / "refined_poses.tum"));
    fs::remove_all(off);
}

TEST(PndtMapCli, AnInputThatIsTheRunsOwnMapsRawlogIsRefusedUntouched)
{
    // Replaying <out>/maps.rawlog into <out> truncated it before it was read (38 MB -> 20 bytes,
    // then "the rawlog holds no observations").
    const fs::path out = tempDir("own_output");
    RunResult r = run(mapExe() + roomRawlog().string() + " --period 2 --rawlog-inputs -o " + out.string());
    ASSERT_EQ(r.code, 0) << r.out;
    const auto size = fs::file_size(out / "maps.rawlog");
    for (const std::string& args : {std::string(" -o ") + out.string(), " --keep-maps 2 -o " + out.string()})
    {
        r = run(mapExe() + (out / "maps.rawlog").string() + " --period 2" + args);
        EXPECT_EQ(r.code, 1) << r.out;
        EXPECT_NE(r.out.find((out / "maps.rawlog").string() + " is this run's own maps rawlog"), std::string::npos)
            << r.out;
        EXPECT_EQ(fs::file_size(out / "maps.rawlog"), size);
    }
    // Into another folder it replays.
    r = run(mapExe() + (out / "maps.rawlog").string() + " --period 2 -o " + (out / "again").string());
    EXPECT_EQ(r.code, 0) << r.out;
    fs::remove_all(out);
}

TEST(PndtMapCli, ARunThatMapsNothingLeavesTheEarlierRunsFilesAsTheyWere)
{
    // A failed or empty run truncated the earlier run's maps.rawlog (to 20 bytes) and kept its
    // index.json and maps: the folder then contradicted itself.
    const fs::path out = tempDir("nothing_mapped");
    RunResult r = run(mapExe() + roomRawlog().string() + " --period 2 -o " + out.string());
    ASSERT_EQ(r.code, 0) << r.out;
    auto slurp = [](const fs::path& p) {
        std::ifstream f(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    };
    const std::string rawlog = slurp(out / "maps.rawlog"), index = slurp(out / "index.json");
    // Every frame from another sensor: nothing mapped.
    r = run(mapExe() + roomRawlog().string() + " --period 2 -s pndt-map.rgbd_label=FOO -o " + out.string());
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("no frame could be mapped (0 range scans, 0 without a pose within 0.1 s, 40 of sensors other "
                         "than rgbd_label 'FOO'); the output folder holds no map of this run"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("note: " + out.string() + " holds 3 map file(s) (map_0000.pndt.gz .. map_0002.pndt.gz) and "
                         "1 maps rawlog(s) (maps.rawlog) of an earlier run"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(slurp(out / "maps.rawlog"), rawlog);
    EXPECT_EQ(slurp(out / "index.json"), index);
    fs::remove_all(out);
}

TEST(PndtMapCli, PaperPresetBuildsAMapWithThePapersRulesAndLayersWithHypersim)
{
    const fs::path out = tempDir("paper");
    const RunResult r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " --preset paper,hypersim");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto map = pndt::loadMapArchive((out / "map_0000.pndt.gz").string());
    pndt::MapOptions expected;
    expected.applyPaperRules();
    const pndt::MapOptions& o = map->core().options();
    // The map file keeps the rules it was built with.
    EXPECT_EQ(o.ray_mode, expected.ray_mode);
    EXPECT_EQ(o.miss_accumulation, expected.miss_accumulation);
    EXPECT_EQ(o.instance_class_voxels, expected.instance_class_voxels);
    EXPECT_EQ(o.semantic_eviction, expected.semantic_eviction);
    EXPECT_EQ(o.void_bin, expected.void_bin);
    EXPECT_EQ(o.reset_freed_voxels, expected.reset_freed_voxels);
    EXPECT_FALSE(o.class_consistent_instances);
    EXPECT_EQ(o.label_fill_distance, 0.0);
    // hypersim.ini, layered after paper.ini.
    EXPECT_EQ(o.theta_z, 0.4);
    EXPECT_EQ(o.max_range, 20.0);
    EXPECT_GT(map->core().instances().size(), 0u);
    const RunResult bad = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " --preset papers");
    EXPECT_NE(bad.code, 0);
    EXPECT_NE(bad.out.find("papers"), std::string::npos) << bad.out;
}

TEST(PndtMapCli, ADepthFrameStampedBeforeTheFrameBeforeIsSkippedAndCounted)
{
    const fs::path out = tempDir("stamp_back");
    RunResult r = run(mapExe() + roomRawlog().string() + " -o " + (out / "ref").string());
    ASSERT_EQ(r.code, 0) << r.out;
    // Frame 5 again (its scan and label images) just before frame 31's scan, as a camera whose
    // clock started again would stamp it: mapped with frame 5's pose it would add its
    // surfaces a second time; skipped, the map is the reference's, bit for bit.
    const fs::path again = rewrittenRoom(out / "again.rawlog", [](auto& obs) {
        std::vector<size_t> scans;
        for (size_t i = 0; i < obs.size(); ++i)
            if (std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(obs[i])) scans.push_back(i);
        ASSERT_GE(scans.size(), 32u);
        std::vector<mrpt::obs::CObservation::Ptr> copy;
        for (size_t i = scans[5]; i < obs.size() && obs[i]->timestamp == obs[scans[5]]->timestamp; ++i)
            copy.push_back(obs[i]);
        ASSERT_EQ(copy.size(), 3u);  // the scan and its two label images
        obs.insert(obs.begin() + long(scans[31]), copy.begin(), copy.end());
    });
    r = run(mapExe() + again.string() + " -o " + (out / "again").string());
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("again.rawlog: depth frame 32 at t="), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("is not after the frame before (t="), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("frames mapped      : 40 (40 with labels"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(", 1 stamped no later than the frame before"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("label images       : 2 without a matching depth frame"), std::string::npos) << r.out;
    EXPECT_TRUE(mapBytes(out / "again") == mapBytes(out / "ref")) << "the map differs from the reference";
}

TEST(PndtMapCli, LabelImagesWithoutDepthAreCounted)
{
    const fs::path out = tempDir("labels_only");
    const Room room(6);
    std::mt19937 rng(1);
    {
        pndt::RawlogFrameWriter w((out / "in.rawlog").string());
        for (int i = 0; i < 6; ++i)
        {
            pndt::PanopticFrame f = room.frame(i, rng);
            if (i % 2 == 0)
                w.write(f, stampOf(i), room.poses[size_t(i)]);
            else
            {
                // Only the label images of this frame, no depth.
                mrpt::obs::CObservationImage sem, inst;
                pndt::labelImagesFrom(f, "RGBD", mrpt::Clock::fromDouble(stampOf(i)), sem, inst);
                w.writeObservation(sem);
                w.writeObservation(inst);
            }
        }
        w.commit();
    }
    const RunResult r = run(mapExe() + (out / "in.rawlog").string() + " -o " + (out / "m").string());
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("frames mapped      : 3 (3 with labels"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("label images       : 6 without a matching depth frame"), std::string::npos) << r.out;
}

namespace
{
/// Starts pndt-map in the background; returns its pid.
pid_t spawn(const std::string& input, const fs::path& out, const std::string& extra)
{
    const pid_t pid = ::fork();
    if (pid == 0)
    {
        const std::string cmd = mapExe() + input + " -o " + out.string() + " " + extra + " > " +
                                (out.string() + ".log") + " 2>&1";
        ::execl("/bin/sh", "sh", "-c", ("exec " + cmd).c_str(), nullptr);
        ::_exit(127);
    }
    return pid;
}
int waitExit(pid_t pid)
{
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}
/// Every map file in `dir` loads completely.
void expectAllMapsLoad(const fs::path& dir, size_t min_maps)
{
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir))
    {
        const std::string name = e.path().filename().string();
        if (name.rfind("map_", 0) != 0 || e.path().extension() != ".gz") continue;
        EXPECT_NO_THROW(loadMapArchive(e.path().string())) << name;
        ++n;
    }
    EXPECT_GE(n, min_maps);
}
}  // namespace

TEST(PndtMapCli, KilledMidRunLeavesNoHalfWrittenMap)
{
    // A longer input and many small maps, so the kill lands while maps are written.
    const fs::path out = tempDir("kill");
    Room(160).writeRawlog((out / "long.rawlog").string(), 160);
    for (int attempt = 0; attempt < 3; ++attempt)
    {
        const fs::path maps = out / ("maps" + std::to_string(attempt));
        fs::create_directories(maps);
        const pid_t pid = spawn((out / "long.rawlog").string(), maps, "--period 0.25 --voxel-size 0.05");
        std::this_thread::sleep_for(std::chrono::milliseconds(1500 + 400 * attempt));
        ::kill(pid, SIGKILL);
        waitExit(pid);
        expectAllMapsLoad(maps, 0);
        if (fs::exists(maps / "index.json"))
        {
            EXPECT_NO_THROW(readJson(maps / "index.json"));
        }
    }
}

TEST(PndtMapCli, CtrlCFinalisesAndWritesTheCurrentMap)
{
    const fs::path out = tempDir("sigint");
    Room(160).writeRawlog((out / "long.rawlog").string(), 160);
    const fs::path maps = out / "maps";
    fs::create_directories(maps);
    const pid_t pid = spawn((out / "long.rawlog").string(), maps, "--voxel-size 0.05");
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    ::kill(pid, SIGINT);
    const int code = waitExit(pid);
    std::ifstream log(maps.string() + ".log");
    const std::string text((std::istreambuf_iterator<char>(log)), {});
    if (code == 0)
        GTEST_SKIP() << "the run finished before the signal: " << text;
    EXPECT_EQ(code, 130) << text;
    EXPECT_NE(text.find("interrupted; the current map was finalised and written"), std::string::npos) << text;
    expectAllMapsLoad(maps, 1);
    EXPECT_EQ(readJson(maps / "index.json").size(), 1u);
}

TEST(PndtMapCli, RawlogEditReadsTheWrittenMapsWithThePlugin)
{
    const fs::path out = tempDir("rawlog_edit");
    ASSERT_EQ(run(mapExe() + roomRawlog().string() + " -o " + out.string()).code, 0);
    const RunResult r =
        run(std::string("rawlog-edit -p ") + PNDT_PLUGIN_PATH + " --info -i " + (out / "map_0000.pndt.gz").string());
    EXPECT_NE(r.out.find("Overall number of objects         : 1"), std::string::npos) << r.out;
    // And the input rawlog opens in stock rawlog-edit without it.
    const RunResult in = run("rawlog-edit --info -i " + roomRawlog().string());
    EXPECT_NE(in.out.find("GT_POSE, RGBD, RGBD_PANOPTIC_INSTANCE, RGBD_PANOPTIC_SEMANTIC"), std::string::npos)
        << in.out;
}

TEST(PndtMapCli, OffscreenScreenshotShowsTheMapInClassColours)
{
    const fs::path out = tempDir("screenshot");
    const RunResult r = run(mapExe() + roomRawlog().string() + " -o " + out.string() + " --screenshot " +
                            (out / "shot.png").string());
    ASSERT_EQ(r.code, 0) << r.out;
    const cv::Mat img = cv::imread((out / "shot.png").string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(img.empty());
    EXPECT_EQ(img.cols, 1024);
    // The wall (class 1) and floor (class 2) colours of the NYUv2 palette are there.
    size_t wall = 0, floor = 0;
    for (int y = 0; y < img.rows; ++y)
        for (int x = 0; x < img.cols; ++x)
        {
            const cv::Vec3b px = img.at<cv::Vec3b>(y, x);  // BGR
            wall += px[2] == 128 && px[1] == 0 && px[0] == 0;
            floor += px[2] == 0 && px[1] == 128 && px[0] == 0;
        }
    EXPECT_GT(wall, 500u);
    EXPECT_GT(floor, 500u);
}
