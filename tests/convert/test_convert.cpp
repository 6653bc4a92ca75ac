// pndt-convert on small folders written by the tests: what ends up in the rawlog (order, stamps,
// depth, poses, labels) for Redwood, TUM and nicr inputs, with the sequence's own and with external
// poses.
#include <fmt/format.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <nlohmann/json.hpp>

#include "convert.h"
#include "convert_fixtures.h"
#include "rawlog_map.h"

using namespace pndt;
using namespace pndt::convert;
using namespace pndt::convert::test;
using mrpt::obs::CObservation3DRangeScan;
using mrpt::obs::CObservationImage;
using mrpt::obs::CObservationRobotPose;

namespace
{
RunResult runConvert(const std::vector<std::string>& args) { return runExe(PNDT_CONVERT_EXE, args); }

nlohmann::json summary(const std::string& p) { return nlohmann::json::parse(slurp(p)); }

/// Checks a range scan against the fixture depth of frame i (mm).
void expectFixtureDepth(const CObservation3DRangeScan& s, int i)
{
    ASSERT_TRUE(s.hasRangeImage);
    ASSERT_EQ(s.rangeImage.cols(), kW);
    ASSERT_EQ(s.rangeImage.rows(), kH);
    EXPECT_FLOAT_EQ(s.rangeUnits, 0.001f);
    EXPECT_TRUE(s.range_is_depth);
    int bad = 0;
    for (int r = 0; r < kH; ++r)
        for (int c = 0; c < kW; ++c)
            if (s.rangeImage(r, c) != fixtureDepthMm(i, r, c)) ++bad;
    EXPECT_EQ(bad, 0) << "frame " << i;
    EXPECT_DOUBLE_EQ(s.cameraParams.fx(), kFx);
    EXPECT_DOUBLE_EQ(s.cameraParams.fy(), kFy);
    EXPECT_DOUBLE_EQ(s.cameraParams.cx(), kCx);
    EXPECT_DOUBLE_EQ(s.cameraParams.cy(), kCy);
}

double stampOf(const mrpt::obs::CObservation& o) { return mrpt::Clock::toDouble(o.timestamp); }

/// A TUM RGB-D folder: depth (5000 units/m) at `depth_stamps` (seconds after kTumBase), rgb 5 ms
/// later, ground truth at `gt_stamps` with pose tumGt(t).
constexpr double kTumBase = 1305031100.0;
Pose tumGt(double dt)
{
    Pose T = Pose::Identity();
    T.linear() = Eigen::AngleAxisd(dt, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(dt, 2 * dt, 0.5);
    return T;
}
std::string tumPoseLine(double t, const Pose& T)
{
    const Eigen::Quaterniond q(T.rotation());
    return fmt::format("{:.6f} {:.9f} {:.9f} {:.9f} {:.12f} {:.12f} {:.12f} {:.12f}\n", t, T.translation().x(),
                       T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(), q.w());
}
void makeTumFolder(const std::string& dir, const std::vector<double>& depth_stamps, const std::vector<double>& gt_stamps)
{
    fs::create_directories(fs::path(dir) / "rgb");
    fs::create_directories(fs::path(dir) / "depth");
    std::string rgb_txt = "# color images\n# file: 'fixture'\n# timestamp filename\n";
    std::string depth_txt = "# depth maps\n# file: 'fixture'\n# timestamp filename\n";
    for (size_t i = 0; i < depth_stamps.size(); ++i)
    {
        const std::string td = fmt::format("{:.6f}", kTumBase + depth_stamps[i]);
        const std::string tc = fmt::format("{:.6f}", kTumBase + depth_stamps[i] + 0.005);
        writePng16((fs::path(dir) / "depth" / (td + ".png")).string(), fixtureDepth(int(i), kW, kH, 5.0));
        cv::imwrite((fs::path(dir) / "rgb" / (tc + ".png")).string(), cv::Mat(kH, kW, CV_8UC3, cv::Scalar(1, 2, 3)));
        rgb_txt += tc + " rgb/" + tc + ".png\n";
        depth_txt += td + " depth/" + td + ".png\n";
    }
    std::ofstream(fs::path(dir) / "rgb.txt") << rgb_txt;
    std::ofstream(fs::path(dir) / "depth.txt") << depth_txt;
    std::string gt = "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n";
    for (double t : gt_stamps) gt += tumPoseLine(kTumBase + t, tumGt(t));
    std::ofstream(fs::path(dir) / "groundtruth.txt") << gt;
    std::ofstream(fs::path(dir) / "intrinsics.json") << open3dIntrinsicsJson(kW, kH, kFx, kFy, kCx, kCy);
}
}  // namespace

using ConvertRedwood = TempDirTest;
using ConvertTum = TempDirTest;
using ConvertNicr = TempDirTest;

// Redwood's world is its first camera (y down): the floor plan and pndt-nav took a wall for the
// floor. Without --level that is said; with it the world is turned so that up is +z.
TEST_F(ConvertRedwood, LevelTurnsTheWorldSoThatTheCamerasUpIsZ)
{
    const std::string in = makeRedwoodFolder(folder("redwood"));
    const RunResult plain = runConvert({in, "-o", path("plain.rawlog")});
    ASSERT_EQ(plain.exit_code, 0) << plain.err;
    EXPECT_TRUE(contains(plain.out, "note: the poses' up (a robot's z, a camera's -y) points along world (0.00, "
                                    "-1.00, 0.00) on average, 90 degrees from +z"))
        << plain.out;
    EXPECT_TRUE(contains(plain.out, "--level writes the rawlog in a world turned to z up")) << plain.out;

    // The turn that takes the cameras' up (0, -1, 0) to +z: -90 degrees about x.
    Pose R = Pose::Identity();
    R.linear() << 1, 0, 0, 0, 0, 1, 0, -1, 0;
    for (const std::vector<std::string>& extra :
         {std::vector<std::string>{"--level"}, std::vector<std::string>{"--level", "--up", "0 -1 0"}})
    {
        std::vector<std::string> args{in, "-o", path("level.rawlog"), "--summary-json", path("level.json")};
        args.insert(args.end(), extra.begin(), extra.end());
        const RunResult r = runConvert(args);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_TRUE(contains(r.out, "world levelled     : up (0.000, -1.000, 0.000)")) << r.out;
        EXPECT_TRUE(contains(r.out, "turned to +z (90.0 degrees)")) << r.out;
        EXPECT_FALSE(contains(r.out, "up (a robot's z, a camera's -y) points")) << r.out;
        const auto objs = readRawlog(path("level.rawlog"));
        ASSERT_EQ(objs.size(), 6u);
        for (int i = 0; i < 3; ++i)
        {
            const auto pose = as<CObservationRobotPose>(objs[size_t(2 * i)]);
            const auto scan = as<CObservation3DRangeScan>(objs[size_t(2 * i + 1)]);
            ASSERT_TRUE(pose && scan);
            const Pose T = cameraPoseInWorld(pose->pose.mean, scan->sensorPose);
            EXPECT_LT(poseDiff(T, R * fixturePose(i)), 1e-9) << i;
            EXPECT_LT((-T.linear().col(1) - Eigen::Vector3d::UnitZ()).norm(), 1e-9) << "frame " << i << " upright";
        }
        const auto j = summary(path("level.json"));
        EXPECT_NEAR(j["levelled"]["degrees"].get<double>(), 90.0, 1e-9);
        fs::remove(path("level.rawlog"));
    }
    // A z-up world is left as it is: robot poses (z up) with the camera mounted upside down. The
    // camera's -y points down there, but the robot's z is the poses' up (the mount says so).
    {
        std::ofstream f(path("robot.tum"));
        for (int i = 0; i < 3; ++i) f << i / 30.0 << " " << 0.01 * i << " 0 0 0 0 0 1\n";
    }
    for (const bool level : {false, true})
    {
        std::vector<std::string> args{in, "-o", path("robot.rawlog"), "--poses", path("robot.tum"), "--pose-format",
                                      "tum", "--pose-frame", "robot", "--sensor-pose", "0 0 1 0 0 180"};
        if (level) args.push_back("--level");
        const RunResult r = runConvert(args);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_FALSE(contains(r.out, "points along world")) << r.out;
        if (level)
        {
            EXPECT_TRUE(contains(r.out, "world levelled     : the first frame's up (0.000, 0.000, 1.000) is nearest "
                                        "+z: not turned"))
                << r.out;
        }
        fs::remove(path("robot.rawlog"));
    }
    // --up without --model or --level is still an error.
    const RunResult up_only = runConvert({in, "-o", path("up.rawlog"), "--up", "0 -1 0"});
    EXPECT_NE(up_only.exit_code, 0);
    EXPECT_TRUE(contains(up_only.err, "--up is for the segmentation front-end (--model) and --level")) << up_only.err;
}

TEST_F(ConvertRedwood, WritesPoseThenScanPerFrameWithKnownDepthAndPoses)
{
    const std::string in = makeRedwoodFolder(folder("redwood"));
    const std::string out = path("out/seq.rawlog"), js = path("out/summary.json");
    const RunResult r = runConvert({in, "-o", out, "--summary-json", js});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    EXPECT_TRUE(contains(r.out, "frames written     : 3")) << r.out;
    EXPECT_TRUE(contains(r.out, "frames skipped     : 0")) << r.out;

    const auto objs = readRawlog(out);
    ASSERT_EQ(objs.size(), 6u);  // (robot pose, scan) x 3, no labels
    for (int i = 0; i < 3; ++i)
    {
        const auto pose = as<CObservationRobotPose>(objs[size_t(2 * i)]);
        const auto scan = as<CObservation3DRangeScan>(objs[size_t(2 * i + 1)]);
        ASSERT_TRUE(pose && scan) << "object order at frame " << i;
        EXPECT_EQ(pose->sensorLabel, "GT_POSE");
        EXPECT_EQ(scan->sensorLabel, "RGBD");
        EXPECT_EQ(pose->timestamp, scan->timestamp);
        EXPECT_NEAR(stampOf(*scan), i / 30.0, 1e-6);
        expectFixtureDepth(*scan, i);
        EXPECT_LT(poseDiff(cameraPoseInWorld(pose->pose.mean, scan->sensorPose), fixturePose(i)), 1e-9);
        ASSERT_TRUE(scan->hasIntensityImage);
        EXPECT_EQ(scan->intensityImage.getWidth(), size_t(kW));
        EXPECT_TRUE(scan->intensityImage.isColor());
    }
    const auto j = summary(js);
    EXPECT_EQ(j["kind"], "redwood");
    EXPECT_EQ(j["frames_written"], 3);
    EXPECT_EQ(j["frames_with_labels"], 0);
    EXPECT_EQ(j["frames_with_color"], 3);
    EXPECT_EQ(j["frames_skipped"], 0);
}

TEST_F(ConvertRedwood, ExternalRedwoodLogReplacesTheFoldersOwnByIndex)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 3, /*trajectory=*/false);
    // Frame i takes block i + 1 of a 4-block file (--pose-index-offset 1).
    std::string log;
    for (int i = 0; i < 4; ++i) log += redwoodLogBlock(i, fixturePose(3 - i));
    const std::string poses = write("poses/other.log", log);
    const std::string out = path("out.rawlog");
    const RunResult r =
        runConvert({in, "-o", out, "--poses", poses, "--pose-format", "redwood", "--pose-index-offset", "1", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "matched by index")) << r.out;
    const auto objs = readRawlog(out);
    ASSERT_EQ(objs.size(), 6u);
    for (int i = 0; i < 3; ++i)
    {
        const auto pose = as<CObservationRobotPose>(objs[size_t(2 * i)]);
        ASSERT_TRUE(pose);
        EXPECT_LT(poseDiff(cameraPoseInWorld(pose->pose.mean, mrpt::poses::CPose3D()), fixturePose(3 - (i + 1))),
                  1e-9);
    }
}

TEST_F(ConvertRedwood, StartStrideAndMaxFramesSelectFrames)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 3);
    const std::string out = path("out.rawlog"), js = path("s.json");
    const RunResult r = runConvert({in, "-o", out, "--start", "1", "--stride", "2", "--no-color", "-q", "--summary-json",
                                    js, "--stamp-offset", "1700000000"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto objs = readRawlog(out);
    ASSERT_EQ(objs.size(), 2u);
    const auto scan = as<CObservation3DRangeScan>(objs[1]);
    ASSERT_TRUE(scan);
    expectFixtureDepth(*scan, 1);
    EXPECT_NEAR(stampOf(*scan), 1700000000.0 + 1 / 30.0, 1e-6);
    EXPECT_FALSE(scan->hasIntensityImage);
    const auto pose = as<CObservationRobotPose>(objs[0]);
    ASSERT_TRUE(pose);
    EXPECT_LT(poseDiff(cameraPoseInWorld(pose->pose.mean, scan->sensorPose), fixturePose(1)), 1e-9);
    EXPECT_EQ(summary(js)["frames_selected"], 1);
}

TEST_F(ConvertRedwood, SensorPoseMakesTheRobotPoseTheRobots)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 2);
    const std::string out = path("out.rawlog");
    const RunResult r = runConvert({in, "-o", out, "--sensor-pose", "0.2 0 1.1 0 10 0", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto objs = readRawlog(out);
    ASSERT_EQ(objs.size(), 4u);
    const mrpt::poses::CPose3D sensor(0.2, 0, 1.1, 0, 10 * M_PI / 180, 0);
    for (int i = 0; i < 2; ++i)
    {
        const auto pose = as<CObservationRobotPose>(objs[size_t(2 * i)]);
        const auto scan = as<CObservation3DRangeScan>(objs[size_t(2 * i + 1)]);
        ASSERT_TRUE(pose && scan);
        EXPECT_LT(poseDiff(toEigen(scan->sensorPose), toEigen(sensor)), 1e-12);
        // The camera is where the .log says; the robot pose is the camera minus the extrinsic.
        EXPECT_LT(poseDiff(cameraPoseInWorld(pose->pose.mean, scan->sensorPose), fixturePose(i)), 1e-9);
        EXPECT_GT(poseDiff(toEigen(pose->pose.mean), toEigen(mrptSensorPoseOf(fixturePose(i)))), 0.1);
    }
}

TEST_F(ConvertTum, InterpolatesGroundTruthAtDepthStampsAndSkipsUnposedFrames)
{
    const std::string dir = folder("tum");
    // Frames at 0.05, 0.15, 0.25 (inside 10 Hz ground truth), 0.45 (in a 0.3 s gap), 0.95 (after it).
    makeTumFolder(dir, {0.05, 0.15, 0.25, 0.45, 0.95}, {0.0, 0.1, 0.2, 0.3, 0.6});
    const std::string out = path("out.rawlog"), js = path("s.json");
    const RunResult r =
        runConvert({dir, "-o", out, "--intrinsics", (fs::path(dir) / "intrinsics.json").string(), "--max-pose-gap",
                    "0.12", "--summary-json", js});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = summary(js);
    EXPECT_EQ(j["kind"], "tum");
    EXPECT_EQ(j["frames_in_source"], 5);
    EXPECT_EQ(j["frames_written"], 3);
    EXPECT_EQ(j["frames_skipped"], 2);
    EXPECT_EQ(j["skipped"]["no pose: none in the sequence for this frame"], 2) << j.dump(2);

    const auto objs = readRawlog(out);
    ASSERT_EQ(objs.size(), 6u);
    const double dts[] = {0.05, 0.15, 0.25};
    for (int i = 0; i < 3; ++i)
    {
        const auto pose = as<CObservationRobotPose>(objs[size_t(2 * i)]);
        const auto scan = as<CObservation3DRangeScan>(objs[size_t(2 * i + 1)]);
        ASSERT_TRUE(pose && scan);
        EXPECT_NEAR(stampOf(*scan), kTumBase + dts[i], 2e-6);
        expectFixtureDepth(*scan, i);  // 5000 units per metre in, mm out
        // SLERP about a fixed axis = linear in angle; translation linear.
        EXPECT_LT(poseDiff(cameraPoseInWorld(pose->pose.mean, scan->sensorPose), tumGt(dts[i])), 1e-5);
    }
}

TEST_F(ConvertTum, ExternalRtabmapRobotPosesWithSensorPose)
{
    const std::string dir = folder("tum");
    makeTumFolder(dir, {0.05, 0.15, 0.25}, {});
    fs::remove(fs::path(dir) / "groundtruth.txt");
    // RTAB-Map id 10: "stamp x y z qx qy qz qw" of the robot (base_link) frame.
    std::string txt = "#timestamp x y z qx qy qz qw\n";
    for (double t : {0.0, 0.1, 0.2, 0.3})
        txt += fmt::format("{:.6f} {:.6f} 0 0 0 0 0 1\n", kTumBase + t, t);
    const std::string poses = write("rtabmap_poses.txt", txt);
    const std::string out = path("out.rawlog");
    const RunResult r = runConvert({dir, "-o", out, "--intrinsics", (fs::path(dir) / "intrinsics.json").string(),
                                 "--poses", poses, "--pose-format", "rtabmap10", "--sensor-pose", "0.1 0 0.5 0 0 0",
                                 "--max-pose-gap", "0.12", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "robot poses")) << r.out;
    const auto objs = readRawlog(out);
    ASSERT_EQ(objs.size(), 6u);
    const double dts[] = {0.05, 0.15, 0.25};
    for (int i = 0; i < 3; ++i)
    {
        const auto pose = as<CObservationRobotPose>(objs[size_t(2 * i)]);
        const auto scan = as<CObservation3DRangeScan>(objs[size_t(2 * i + 1)]);
        ASSERT_TRUE(pose && scan);
        // The robot pose observation is the file's robot pose, interpolated at the frame stamp.
        EXPECT_NEAR(pose->pose.mean.x(), dts[i], 1e-5);
        EXPECT_NEAR(pose->pose.mean.y(), 0.0, 1e-9);
        EXPECT_NEAR(pose->pose.mean.yaw(), 0.0, 1e-9);
        EXPECT_NEAR(scan->sensorPose.x(), 0.1, 1e-12);
        EXPECT_NEAR(scan->sensorPose.z(), 0.5, 1e-12);
        // Camera looks along the robot's x axis: optical z = world x.
        const Pose cam = cameraPoseInWorld(pose->pose.mean, scan->sensorPose);
        EXPECT_LT((cam.linear().col(2) - Eigen::Vector3d::UnitX()).norm(), 1e-9);
        EXPECT_LT((cam.translation() - Eigen::Vector3d(dts[i] + 0.1, 0, 0.5)).norm(), 1e-5);
    }
}

TEST_F(ConvertTum, ExternalPoseFileOutsideRangeAndGapsAreCountedByReason)
{
    const std::string dir = folder("tum");
    makeTumFolder(dir, {0.05, 0.15, 0.45, 0.95}, {});
    std::string txt;
    for (double t : {0.0, 0.1, 0.2, 0.3, 0.6}) txt += tumPoseLine(kTumBase + t, tumGt(t));
    const std::string poses = write("gt.txt", txt);
    const std::string out = path("out.rawlog"), js = path("s.json");
    const RunResult r = runConvert({dir, "-o", out, "--intrinsics", (fs::path(dir) / "intrinsics.json").string(),
                                 "--poses", poses, "--pose-format", "tum", "--max-pose-gap", "0.15",
                                 "--summary-json", js, "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = summary(js);
    EXPECT_EQ(j["frames_written"], 2);
    EXPECT_EQ(j["skipped"]["no pose: gap between poses > max-pose-gap"], 1) << j.dump(2);
    EXPECT_EQ(j["skipped"]["no pose: frame outside the pose file's time range"], 1) << j.dump(2);
    EXPECT_TRUE(contains(r.out, "no pose: gap between poses > max-pose-gap")) << r.out;
}

TEST_F(ConvertNicr, PredictionsBecomeTheTwoFloatLabelImages)
{
    const std::string root = folder("nicr/valid");
    makeNicrFolder(root, 3, {0, 2});  // frame 1 (000050) has no prediction
    const std::string out = path("out.rawlog"), js = path("s.json");
    const RunResult r =
        runConvert({root, "-o", out, "--predictions", (fs::path(root) / "mapping").string(), "--summary-json", js});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const auto j = summary(js);
    EXPECT_EQ(j["kind"], "nicr");
    EXPECT_EQ(j["frames_written"], 3);
    EXPECT_EQ(j["frames_with_labels"], 2);
    EXPECT_EQ(j["frames_labels_missing"], 1);

    const auto objs = readRawlog(out);
    ASSERT_EQ(objs.size(), 10u);  // 4 + 2 + 4
    size_t k = 0;
    for (int i = 0; i < 3; ++i)
    {
        const auto pose = as<CObservationRobotPose>(objs[k++]);
        const auto scan = as<CObservation3DRangeScan>(objs[k++]);
        ASSERT_TRUE(pose && scan) << "frame " << i;
        EXPECT_NEAR(stampOf(*scan), i * 50 / 30.0, 1e-6);
        expectFixtureDepth(*scan, i);
        EXPECT_LT(poseDiff(cameraPoseInWorld(pose->pose.mean, scan->sensorPose), fixturePose(i)), 1e-6);
        if (i == 1) continue;
        const auto sem = as<CObservationImage>(objs[k++]);
        const auto ins = as<CObservationImage>(objs[k++]);
        ASSERT_TRUE(sem && ins);
        EXPECT_EQ(sem->sensorLabel, "RGBD_PANOPTIC_SEMANTIC");
        EXPECT_EQ(ins->sensorLabel, "RGBD_PANOPTIC_INSTANCE");
        EXPECT_EQ(sem->timestamp, scan->timestamp);
        EXPECT_EQ(ins->timestamp, scan->timestamp);
        ASSERT_EQ(sem->image.getPixelDepth(), mrpt::img::PixelDepth::D32F);
        ASSERT_EQ(sem->image.getWidth(), size_t(kW));
        ASSERT_EQ(sem->image.getHeight(), size_t(kH));
        int bad = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
            {
                if (std::abs(sem->image.ptrLine<float>(y)[x] - fixtureSemantic(i, y, x)) > 1e-5f) ++bad;
                if (std::abs(ins->image.ptrLine<float>(y)[x] - fixtureInstance(i, y, x)) > 1e-5f) ++bad;
            }
        EXPECT_EQ(bad, 0) << "frame " << i;
    }
}

TEST_F(ConvertNicr, GroundTruthLabelsWithScoreOne)
{
    const std::string root = folder("nicr/valid");
    makeNicrFolder(root, 1, {});
    cv::imwrite(path("nicr/valid/semantic_40/scene0000_00/000000.png"), cv::Mat(kH, kW, CV_8UC1, cv::Scalar(5)));
    const std::string out = path("out.rawlog");
    const RunResult r = runConvert({root, "-o", out, "--labels", "gt", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const auto objs = readRawlog(out);
    ASSERT_EQ(objs.size(), 4u);
    const auto sem = as<CObservationImage>(objs[2]);
    const auto ins = as<CObservationImage>(objs[3]);
    ASSERT_TRUE(sem && ins);
    EXPECT_NEAR(sem->image.ptrLine<float>(3)[4], 5.999f, 1e-5f);
    EXPECT_NEAR(ins->image.ptrLine<float>(3)[4], 0.0f, 1e-6f);  // no instance GT: none
}

TEST_F(ConvertNicr, LibraryReportMatchesTheFolder)
{
    const std::string root = folder("nicr/valid");
    makeNicrFolder(root, 2, {0, 1});
    ConvertOptions o;
    o.input = root;
    o.output = path("lib.rawlog");
    o.predictions_dir = (fs::path(root) / "mapping").string();
    size_t calls = 0, last = 0;
    const ConvertReport rep = convertSequence(o, [&](size_t done, size_t total) {
        ++calls;
        last = done;
        EXPECT_EQ(total, 2u);
    });
    EXPECT_EQ(rep.frames_written, 2u);
    EXPECT_EQ(rep.frames_with_labels, 2u);
    EXPECT_EQ(calls, 3u);
    EXPECT_EQ(last, 2u);
    EXPECT_GT(rep.output_bytes, 0u);
    EXPECT_TRUE(fs::exists(o.output));
}

TEST_F(ConvertNicr, UnregisteredColourIsNotEmbeddedAndSaysSo)
{
    const std::string root = folder("nicr/valid");
    makeNicrFolder(root, 2, {});
    // ScanNet-like: colour larger than depth, with its own intrinsics.
    for (const char* f : {"000000", "000050"})
        cv::imwrite(path(std::string("nicr/valid/rgb/scene0000_00/") + f + ".jpg"),
                    cv::Mat(2 * kH, 2 * kW, CV_8UC3, cv::Scalar(9, 9, 9)));
    write("nicr/valid/rgb_intrinsics/scene0000_00.json", "{\"fx\": 0.9, \"fy\": 1.2, \"cx\": 0.5, \"cy\": 0.5}");
    const std::string out = path("out.rawlog"), js = path("s.json");
    const RunResult r = runConvert({root, "-o", out, "-q", "--summary-json", js});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = summary(js);
    EXPECT_EQ(j["frames_written"], 2);
    EXPECT_EQ(j["frames_with_color"], 0);
    EXPECT_TRUE(contains(r.out, "colour not embedded in 2 frames")) << r.out;
    const auto objs = readRawlog(out);
    ASSERT_EQ(objs.size(), 4u);
    const auto scan = as<CObservation3DRangeScan>(objs[1]);
    ASSERT_TRUE(scan);
    EXPECT_FALSE(scan->hasIntensityImage);
}

TEST_F(ConvertRedwood, RtabmapRawPosesAreRobotPosesMatchedByIndex)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 3, /*trajectory=*/false);
    // RTAB-Map "Raw" (id 0): 3x4 row-major per line, no stamp; robot i at x = i, yawed 90° at i = 2.
    const std::string poses = write("poses.txt",
                                    "1 0 0 0 0 1 0 0 0 0 1 0\n"
                                    "1 0 0 1 0 1 0 0 0 0 1 0\n"
                                    "0 -1 0 2 1 0 0 0 0 0 1 0\n");
    const std::string out = path("out.rawlog");
    const RunResult r = runConvert({in, "-o", out, "--poses", poses, "--pose-format", "rtabmap0", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "robot poses")) << r.out;
    EXPECT_TRUE(contains(r.out, "matched by index")) << r.out;
    const auto objs = readRawlog(out);
    ASSERT_EQ(objs.size(), 6u);
    for (int i = 0; i < 3; ++i)
    {
        const auto pose = as<CObservationRobotPose>(objs[size_t(2 * i)]);
        ASSERT_TRUE(pose);
        EXPECT_NEAR(pose->pose.mean.x(), i, 1e-9);
        EXPECT_NEAR(pose->pose.mean.y(), 0, 1e-9);
        EXPECT_NEAR(pose->pose.mean.yaw(), i == 2 ? M_PI / 2 : 0.0, 1e-9);
    }
    // The camera of frame 2 looks along world +y (the robot's x axis after the 90° yaw).
    const auto scan = as<CObservation3DRangeScan>(objs[5]);
    const Pose cam = cameraPoseInWorld(as<CObservationRobotPose>(objs[4])->pose.mean, scan->sensorPose);
    EXPECT_LT((cam.linear().col(2) - Eigen::Vector3d::UnitY()).norm(), 1e-9);
}

TEST_F(ConvertRedwood, MappingTheRawlogBackSaysWhereADamagedFileStops)
{
    const std::string in = makeRedwoodFolder(folder("redwood"));
    const std::string out = path("seq.rawlog");
    ASSERT_EQ(runConvert({in, "-o", out}).exit_code, 0);
    PanopticNDTMap whole;
    const RawlogMapResult m = mapRawlog(out, whole);
    EXPECT_EQ(m.objects, 6u);
    EXPECT_EQ(m.scans_mapped, 3u);

    // The same file cut in half: an error naming the file, the object and the byte.
    const std::string bytes = slurp(out);
    const std::string cut = path("cut.rawlog");
    std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 2));
    PanopticNDTMap part;
    try
    {
        mapRawlog(cut, part);
        FAIL() << "expected an error for the truncated rawlog";
    }
    catch (const std::runtime_error& e)
    {
        const std::string what = e.what();
        EXPECT_NE(what.find(cut), std::string::npos) << what;
        EXPECT_NE(what.find("truncated or corrupt at object #"), std::string::npos) << what;
    }
}

TEST_F(ConvertRedwood, MappingTheRawlogBackTakesPosesByStampWhereverTheyStand)
{
    // A pndt-live recording holds the localiser's poses as they arrived (all first when sent
    // at once, or after their frames), stamped between the frames: the preview found "no scan
    // with a robot pose" in a recording pndt-map maps.
    const std::string in = makeRedwoodFolder(folder("redwood"));
    const std::string out = path("seq.rawlog");
    ASSERT_EQ(runConvert({in, "-o", out}).exit_code, 0);
    PanopticNDTMap converted;
    const RawlogMapResult ref = mapRawlog(out, converted);
    ASSERT_EQ(ref.scans_mapped, 3u);
    const auto objs = readRawlog(out);
    const auto relocated = [&](const std::string& name, double before, double after) {
        const std::string file = path(name);
        mrpt::io::CFileGZOutputStream f(file);
        auto a = mrpt::serialization::archiveFrom(f);
        for (const auto& o : objs)  // every pose twice, around its scan's stamp, before any scan
            if (auto p = as<CObservationRobotPose>(o))
                for (const double dt : {-before, after})
                {
                    CObservationRobotPose q = *p;
                    q.timestamp = mrpt::Clock::fromDouble(mrpt::Clock::toDouble(p->timestamp) + dt);
                    a << q;
                }
        for (const auto& o : objs)
            if (!as<CObservationRobotPose>(o)) a << *o;
        return file;
    };
    PanopticNDTMap first;
    const RawlogMapResult m = mapRawlog(relocated("poses_first.rawlog", 0.01, 0.02), first);
    EXPECT_EQ(m.robot_poses, 6u);
    EXPECT_EQ(m.scans_mapped, 3u);
    EXPECT_EQ(m.scans_without_pose, 0u);
    EXPECT_EQ(first.core().voxels().size(), converted.core().voxels().size());
    EXPECT_EQ(first.core().occupiedCount(), converted.core().occupiedCount());
    for (size_t i = 0; i < 3; ++i) EXPECT_LT(poseDiff(m.cameras[i], ref.cameras[i]), 1e-9) << i;
    // Poses further from the scans than the gap (0.1 s): no pose for any scan, never a stale one.
    PanopticNDTMap none;
    const RawlogMapResult far = mapRawlog(relocated("poses_far.rawlog", 0.15, 0.15), none);
    EXPECT_EQ(far.scans_mapped, 0u);
    EXPECT_EQ(far.scans_without_pose, 3u);
}

TEST(OverviewCamera, LooksAtTheMapFromTheGivenElevationAndStraightDown)
{
    // A wall 2 m in front of an identity camera; world "up" is the optical -y.
    MapOptions o;
    o.voxel_size = 0.1;
    PanopticMap map(o);
    PanopticFrame f;
    f.K = {32, 24, 20.0, 20.0, 15.5, 11.5};
    f.depth.resize(32, 24, 2.0f);
    for (int i = 0; i < 3; ++i) map.integrate(f, Pose::Identity());
    ASSERT_GT(map.occupiedCount(), 0u);
    const Eigen::Vector3d up(0, -1, 0);
    const std::vector<Pose> cameras = {Pose::Identity()};
    for (const double elevation : {50.0, 90.0})
    {
        const Pose T = overviewCamera(map, cameras, up, f.K, elevation);
        const Eigen::Vector3d z = T.linear().col(2), x = T.linear().col(0), y = T.linear().col(1);
        EXPECT_NEAR(-z.dot(up), std::sin(elevation * M_PI / 180.0), 1e-9) << elevation;  // looking down by it
        EXPECT_NEAR(x.dot(z), 0.0, 1e-12);
        EXPECT_NEAR(y.dot(z), 0.0, 1e-12);
        EXPECT_NEAR(x.cross(y).dot(z), 1.0, 1e-12);  // a rotation
        if (elevation < 90) EXPECT_NEAR(x.dot(up), 0.0, 1e-12);  // horizon level
        else EXPECT_NEAR(-y.dot(Eigen::Vector3d(0, 0, 1)), 1.0, 1e-9);  // straight down: image up = forward
    }
}
