// pndt-convert on bad input: each case either fails with a non-zero exit and a message naming the
// file (and line, for text formats), or — where skipping is right — skips and counts the frame.
// A failed conversion never leaves anything at the output path (nor temporary files).
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "convert_fixtures.h"

using namespace pndt;
using namespace pndt::convert::test;

namespace
{
RunResult runConvert(const std::vector<std::string>& args) { return runExe(PNDT_CONVERT_EXE, args); }

/// Files in `dir` whose name starts with `stem` (the output and any temporary of it).
std::vector<std::string> filesLike(const std::string& dir, const std::string& stem)
{
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().filename().string().rfind(stem, 0) == 0) out.push_back(e.path().string());
    return out;
}

/// Expects failure with every `needles` in stderr and no output (nor temporary) left behind.
void expectFailure(const RunResult& r, const std::string& out, std::initializer_list<std::string> needles)
{
    EXPECT_NE(r.exit_code, 0) << r.out;
    for (const auto& n : needles) EXPECT_TRUE(contains(r.err, n)) << "stderr: " << r.err << "\nshould contain: " << n;
    EXPECT_TRUE(contains(r.err, "pndt-convert: error: ")) << r.err;
    const auto left = filesLike(fs::path(out).parent_path().string(), fs::path(out).filename().string());
    EXPECT_TRUE(left.empty()) << "left behind: " << (left.empty() ? "" : left.front());
}
}  // namespace

using ConvertErrors = TempDirTest;

TEST_F(ConvertErrors, MissingInputFolder)
{
    const std::string out = path("o/out.rawlog");
    const std::string missing = dir() + "/no_such_sequence";
    expectFailure(runConvert({missing, "-o", out}), out, {missing, "input folder not found"});
}

TEST_F(ConvertErrors, FolderOfUnknownLayout)
{
    const std::string in = folder("empty");
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({in, "-o", out}), out, {in, "cannot tell the dataset format"});
}

TEST_F(ConvertErrors, DepthImageOfTheWrongSizeFailsOrIsSkippedOnRequest)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 3);
    const std::string bad = in + "/depth/00001.png";
    writePng16(bad, fixtureDepth(1, kW - 1, kH));
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({in, "-o", out, "-q"}), out, {bad, "31 x 24", "32 x 24"});

    const std::string js = path("o/s.json");
    const RunResult r = runConvert({in, "-o", out, "-q", "--skip-bad-frames", "--summary-json", js});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(js));
    EXPECT_EQ(j["frames_written"], 2);
    EXPECT_EQ(j["skipped"]["unreadable frame"], 1);
    EXPECT_TRUE(contains(r.out, "00001.png")) << r.out;  // the example names the file
    EXPECT_EQ(readRawlog(out).size(), 4u);
}

TEST_F(ConvertErrors, ColourImageOfTheWrongSize)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 2);
    const std::string bad = in + "/image/00000.png";
    cv::imwrite(bad, cv::Mat(kH + 2, kW, CV_8UC3, cv::Scalar(0, 0, 0)));
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({in, "-o", out, "-q"}), out, {bad, "colour"});
    // Without colour the frame is fine.
    EXPECT_EQ(runConvert({in, "-o", out, "-q", "--no-color"}).exit_code, 0);
}

TEST_F(ConvertErrors, CorruptDepthPng)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 3);
    const std::string bad = write("redwood/depth/00002.png", "not a png at all");
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({in, "-o", out, "-q"}), out, {bad});
}

TEST_F(ConvertErrors, MalformedIntrinsicsJson)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 2);
    const std::string bad = write("redwood/camera_primesense.json", "{\"width\": 32, \"height\": ");
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({in, "-o", out}), out, {bad});
}

TEST_F(ConvertErrors, MalformedNicrExtrinsicsJson)
{
    const std::string root = folder("nicr/valid");
    makeNicrFolder(root, 2, {});
    const std::string bad = write("nicr/valid/extrinsics/scene0000_00/000050.json", "{\"x\": 1, \"y\": [}");
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({root, "-o", out}), out, {bad});
}

TEST_F(ConvertErrors, MalformedNpzPrediction)
{
    const std::string root = folder("nicr/valid");
    makeNicrFolder(root, 2, {0, 1});
    const std::string bad = write("nicr/valid/mapping/pred_panoptic_instance/scene0000_00/000050.npz", "PK\x03\x04junk");
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({root, "-o", out, "--predictions", root + "/mapping", "-q"}), out, {bad});
}

TEST_F(ConvertErrors, PredictionOfTheWrongSize)
{
    const std::string root = folder("nicr/valid");
    makeNicrFolder(root, 1, {0});
    const std::string bad = path("nicr/valid/mapping/pred_panoptic_semantic/scene0000_00/000000.npz");
    writeNpz(bad, {1, size_t(kH), size_t(kW / 2)}, std::vector<float>(size_t(kH * kW / 2), 1.5f));
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({root, "-o", out, "--predictions", root + "/mapping", "-q"}), out,
                  {bad, "16 x 24", "32 x 24"});
}

TEST_F(ConvertErrors, NegativePredictionValue)
{
    const std::string root = folder("nicr/valid");
    makeNicrFolder(root, 1, {0});
    const std::string bad = path("nicr/valid/mapping/pred_panoptic_instance/scene0000_00/000000.npz");
    std::vector<float> v(size_t(kH * kW), 2.5f);
    v[5] = -1.f;
    writeNpz(bad, {size_t(kH), size_t(kW)}, v);
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({root, "-o", out, "--predictions", root + "/mapping", "-q"}), out, {bad});
}

TEST_F(ConvertErrors, UnknownPoseFormat)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 2);
    const std::string poses = write("p.txt", "0 0 0 0 0 0 0 1\n");
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({in, "-o", out, "--poses", poses, "--pose-format", "bogus"}), out,
                  {"--pose-format", "bogus", "rtabmap11"});
}

TEST_F(ConvertErrors, PosesWithoutFormatAndFormatWithoutPoses)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 2);
    const std::string poses = write("p.txt", "0 0 0 0 0 0 0 1\n");
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({in, "-o", out, "--poses", poses}), out, {"--pose-format"});
    expectFailure(runConvert({in, "-o", out, "--pose-format", "tum"}), out, {"--poses"});
}

TEST_F(ConvertErrors, MissingPoseFile)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 2);
    const std::string out = path("o/out.rawlog");
    const std::string missing = dir() + "/nope.txt";
    expectFailure(runConvert({in, "-o", out, "--poses", missing, "--pose-format", "tum"}), out, {missing});
}

TEST_F(ConvertErrors, MalformedPoseLineNamesFileAndLine)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 2);
    const std::string poses = write("p.txt", "# t x y z qx qy qz qw\n0.0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 1\n");
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({in, "-o", out, "--poses", poses, "--pose-format", "tum"}), out, {poses, "line 3"});
}

TEST_F(ConvertErrors, NonFinitePoseInExternalFileIsSkippedOrStrictError)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 3, false);
    // Frame stamps are 0, 0.1, 0.2 (--frame-rate 10); the pose at 0.1 is non-finite, so frame 1
    // falls into a 0.2 s gap.
    const std::string poses = write("p.txt", "0.0 0 0 0 0 0 0 1\n0.1 nan 0 0 0 0 0 1\n0.2 0 0 0 0 0 0 1\n");
    const std::string out = path("o/out.rawlog"), js = path("o/s.json");
    const RunResult r = runConvert({in, "-o", out, "--poses", poses, "--pose-format", "tum", "--max-pose-gap", "0.15",
                                 "--frame-rate", "10", "-q", "--summary-json", js});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(js));
    EXPECT_EQ(j["frames_written"], 2);
    EXPECT_EQ(j["non_finite_poses"], 1);
    EXPECT_EQ(j["skipped"]["no pose: gap between poses > max-pose-gap"], 1) << j.dump(2);
    EXPECT_TRUE(contains(r.out, poses + " (line 2)")) << r.out;

    fs::remove(out);
    expectFailure(runConvert({in, "-o", out, "--poses", poses, "--pose-format", "tum", "--frame-rate", "10", "--strict-poses"}),
                  out,
                  {poses, "line 2"});
}

TEST_F(ConvertErrors, NonFinitePoseInTheFoldersLog)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 3, false);
    std::string log;
    for (int i = 0; i < 3; ++i) log += redwoodLogBlock(i, fixturePose(i), /*nan=*/i == 1);
    const std::string traj = write("redwood/trajectory.log", log);
    const std::string out = path("o/out.rawlog"), js = path("o/s.json");
    const RunResult r = runConvert({in, "-o", out, "-q", "--summary-json", js});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(js));
    EXPECT_EQ(j["frames_written"], 2);
    EXPECT_EQ(j["frames_skipped"], 1);
    EXPECT_EQ(j["non_finite_poses"], 1);
    EXPECT_EQ(readRawlog(out).size(), 4u);

    fs::remove(out);
    expectFailure(runConvert({in, "-o", out, "--strict-poses"}), out, {traj, "line 6", "non-finite"});
}

TEST_F(ConvertErrors, NoPoseAtAllWritesNothing)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 2, /*trajectory=*/false);
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({in, "-o", out, "-q"}), out, {"no frame written", "no pose"});
}

TEST_F(ConvertErrors, FailureKeepsAnExistingOutputUntouched)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 3);
    writePng16(in + "/depth/00002.png", fixtureDepth(2, kW, kH - 1));  // fails at the last frame
    const std::string out = write("o/out.rawlog", "previous contents");
    const RunResult r = runConvert({in, "-o", out, "-q"});
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(slurp(out), "previous contents");
    EXPECT_EQ(filesLike(fs::path(out).parent_path().string(), "out.rawlog").size(), 1u);
}

TEST_F(ConvertErrors, BadOptionValues)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 2);
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({in, "-o", out, "--format", "kinect"}), out, {"--format", "kinect"});
    expectFailure(runConvert({in, "-o", out, "--stride", "0"}), out, {"--stride"});
    expectFailure(runConvert({in, "-o", out, "--sensor-pose", "1 2 3"}), out, {"--sensor-pose"});
    expectFailure(runConvert({in, "-o", out, "--labels", "predictions"}), out, {"--labels"});
    expectFailure(runConvert({in, "-o", out, "--max-pose-gap", "-1"}), out, {"--max-pose-gap"});
    const std::string poses = write("p.txt", "0.0 0 0 0 0 0 0 1\n");
    expectFailure(runConvert({in, "-o", out, "--poses", poses, "--pose-format", "tum", "--pose-match", "index"}), out,
                  {"--pose-match index"});
    // CLI11 rejects unknown flags (its own message, non-zero exit).
    EXPECT_NE(runConvert({in, "-o", out, "--no-such-flag"}).exit_code, 0);
    // Values checked whether or not they are used (without --poses, with -q they were taken).
    for (const auto& [option, value] : std::vector<std::pair<std::string, std::string>>{
             {"--pose-frame", "foo"}, {"--pose-match", "foo"}, {"--progress", "foo"}})
    {
        const RunResult r = runConvert({in, "-o", out, option, value, "-q"});
        EXPECT_NE(r.exit_code, 0) << option;
        EXPECT_TRUE(contains(r.err, option + ": foo not in")) << r.err;
        EXPECT_FALSE(fs::exists(out)) << option;
    }
    // Options of --poses FILE without it: taken and ignored before (a sequence's own robot
    // poses mapped as camera poses, exit 0).
    for (const auto& [option, value] : std::vector<std::pair<std::string, std::string>>{
             {"--pose-frame", "robot"}, {"--pose-match", "index"}, {"--pose-time-offset", "10"},
             {"--pose-index-offset", "1"}})
        expectFailure(runConvert({in, "-o", out, option, value}), out, {option + " given without --poses FILE"});
}

// A rawlog holds millimetres in 16 bits: a depth scale that puts the depths out of that range
// wrote a rawlog without depth, exit 0 (pndt-map then mapped nothing).
TEST_F(ConvertErrors, DepthsARawlogCannotHoldAreAnErrorWhenMostAndANoteWhenFew)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 2);
    const std::string out = path("o/out.rawlog");
    // 1000-1200 units read as metres: 1000-1200 m, all beyond 65.535 m.
    expectFailure(runConvert({in, "-o", out, "--depth-scale", "1"}), out,
                  {"depth pixels (100.0 %) are outside the 0.5 mm - 65.535 m a rawlog stores", "--depth-scale",
                   "1 units per metre"});
    // One pixel at 65.535 m (the largest uint16 in millimetres): written as no depth, said.
    cv::Mat d = fixtureDepth(1, kW, kH);
    d.at<uint16_t>(3, 4) = 65535;
    writePng16(in + "/depth/00001.png", d);
    const RunResult r = runConvert({in, "-o", out});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, fmt::format("note: 1 of {} depth pixels", 2 * (kW * kH - 1))))
        << r.out;
}

TEST_F(ConvertErrors, NicrWithSeveralSequencesNeedsOne)
{
    const std::string root = folder("nicr/valid");
    makeNicrFolder(root, 1, {});
    fs::create_directories(root + "/depth/scene0001_00");
    writePng16(root + "/depth/scene0001_00/000000.png", fixtureDepth(0, kW, kH));
    const std::string out = path("o/out.rawlog");
    expectFailure(runConvert({root, "-o", out}), out, {"--sequence", "scene0000_00", "scene0001_00"});
    const std::string js = path("o/s.json");
    const RunResult r = runConvert({root, "-o", out, "--sequence", "scene0000_00", "-q"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
}

// pndt-rawlog-preview took --up unchecked: "0 0 0" or NaN failed after mapping, in lookAt
// ("viewing direction parallel to the up vector"), naming no option, with a PNG written.
TEST_F(ConvertErrors, RawlogPreviewChecksItsOptionsBeforeReading)
{
    const std::string in = makeRedwoodFolder(folder("redwood"), 2);
    const std::string rawlog = path("seq.rawlog");
    ASSERT_EQ(runConvert({in, "-o", rawlog, "-q"}).exit_code, 0);
    for (const auto& [args, message] : std::vector<std::pair<std::vector<std::string>, std::string>>{
             {{"--up", "0", "0", "0"}, "--up: \"0 0 0\" is not a direction"},
             {{"--up", "nan", "0", "1"}, "--up: \"nan 0 1\" is not a direction"},
             {{"--elevation", "90.5"}, "--elevation: 90.5 is not an angle above the horizon"},
             {{"--tol-abs", "-1"}, "--tol-abs / --tol-rel"}})
    {
        std::vector<std::string> a{rawlog, "-o", path("pv/p"), "-q"};
        a.insert(a.end(), args.begin(), args.end());
        const RunResult r = runExe(PNDT_PREVIEW_EXE, a);
        EXPECT_EQ(r.exit_code, 1) << message;
        EXPECT_TRUE(contains(r.err, "pndt-rawlog-preview: error: " + message)) << r.err;
        EXPECT_FALSE(fs::exists(path("pv/p_first_camera.png"))) << message;
        EXPECT_FALSE(fs::exists(path("pv/p_overview.png"))) << message;
    }
    // A valid --up still maps and writes both views; 90 degrees looks straight down.
    const RunResult ok =
        runExe(PNDT_PREVIEW_EXE, {rawlog, "-o", path("pv/p"), "-q", "--up", "0", "-1", "0", "--elevation", "90"});
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_TRUE(fs::exists(path("pv/p_first_camera.png")));
    EXPECT_TRUE(fs::exists(path("pv/p_overview.png")));
}
