// pndt-live end to end on the OpenNI2 virtual camera (libPndtVirtualCamera.so.0, loaded by the
// real OpenNI2 runtime from <build>/lib/OpenNI2/Drivers), with the camera's true poses sent
// over TCP by pndt-pose-send.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace fs = std::filesystem;

namespace
{
std::string slurp(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}
std::string gunzip(const fs::path& p)
{
    gzFile f = gzopen(p.c_str(), "rb");
    EXPECT_TRUE(f) << p;
    std::string out;
    char buf[1 << 16];
    int n;
    while (f && (n = gzread(f, buf, sizeof buf)) > 0) out.append(buf, size_t(n));
    if (f) gzclose(f);
    return out;
}
int sh(const std::string& cmd)
{
    const int rc = std::system(cmd.c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}
uint64_t number(const std::string& text, const std::string& regex)
{
    std::smatch m;
    EXPECT_TRUE(std::regex_search(text, m, std::regex(regex))) << regex << "\n" << text;
    return m.size() > 1 ? std::stoull(m[1]) : 0;
}

class LiveCli : public ::testing::Test
{
   protected:
    void SetUp() override
    {
        dir = fs::temp_directory_path() /
              fmt::format("pndt_live_{}_{}", ::getpid(), ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
        port = 20000 + (::getpid() * 7 + std::hash<std::string>{}(dir.string())) % 20000;
    }
    void TearDown() override
    {
        if (!HasFailure()) fs::remove_all(dir);
    }
    void camera(const std::string& extra)
    {
        std::ofstream(dir / "camera.cfg") << "width = 640\nheight = 480\nfps = 30\nloop_frames = 30\npose_seconds = 20\n"
                                          << extra;
        ASSERT_EQ(sh(fmt::format("{} --config {} --write-poses {} > /dev/null", PNDT_VIRTUAL_CAMERA_EXE,
                                 (dir / "camera.cfg").string(), (dir / "poses.txt").string())),
                  0);
    }
    /// pndt-live on the virtual camera with poses sent over TCP; returns its exit code.
    int live(const std::string& live_args, const std::string& send_args = "--rate 0")
    {
        const std::string env =
            fmt::format("PNDT_VIRTUAL_CAMERA={} LD_LIBRARY_PATH={}", (dir / "camera.cfg").string(), PNDT_ONI_DIR);
        const std::string cmd = fmt::format(
            "cd {0} && ({1} {2} --pose-tcp {3} --pose-format tum -o {0}/live {4} > live.out 2> live.err; echo $? > "
            "live.rc) & "
            "{5} {0}/poses.txt --to 127.0.0.1:{3} {6} > send.out 2>&1; wait",
            dir.string(), env, PNDT_LIVE_EXE, port, live_args, PNDT_POSE_SEND_EXE, send_args);
        sh(cmd);
        out = slurp(dir / "live.out");
        err = slurp(dir / "live.err");
        return std::stoi(slurp(dir / "live.rc"));
    }
    fs::path dir;
    int port = 0;
    std::string out, err;
};
}  // namespace

TEST_F(LiveCli, MapsTheVirtualCameraAndEqualsTheOfflineReplayOfItsRecording)
{
    camera("");
    ASSERT_EQ(live("--max-frames 75 --period 1 --record rec.rawlog"), 0) << out << err;
    const uint64_t captured = number(out, R"(frames captured\s+: (\d+))");
    const uint64_t mapped = number(out, R"(frames mapped\s+: (\d+))");
    EXPECT_EQ(captured, 75u);
    EXPECT_EQ(mapped, captured) << out;  // nothing dropped or skipped: poses were all there
    EXPECT_NE(out.find("capture"), std::string::npos);
    ASSERT_TRUE(fs::exists(dir / "rec.rawlog"));

    ASSERT_EQ(sh(fmt::format("cd {0} && {1} rec.rawlog -o {0}/replay --period 1 --no-progress > replay.out 2>&1",
                             dir.string(), PNDT_MAP_EXE)),
              0)
        << slurp(dir / "replay.out");
    const std::string replay = slurp(dir / "replay.out");
    EXPECT_EQ(number(replay, R"(frames mapped\s+: (\d+))"), mapped);
    std::vector<std::string> maps;
    for (const auto& e : fs::directory_iterator(dir / "live"))
        if (e.path().extension() == ".gz") maps.push_back(e.path().filename());
    std::sort(maps.begin(), maps.end());
    ASSERT_GE(maps.size(), 2u);  // 2.5 s at a 1 s period: several short-term maps
    for (const auto& m : maps)
    {
        ASSERT_TRUE(fs::exists(dir / "replay" / m)) << m;
        const std::string a = gunzip(dir / "live" / m), b = gunzip(dir / "replay" / m);
        EXPECT_GT(a.size(), 1000u);
        EXPECT_TRUE(a == b) << m << " differs between pndt-live and the replay of its recording";
    }
}

TEST_F(LiveCli, CameraUnpluggedMidRunWritesTheMapAndExitsWithCode4)
{
    camera("unplug_after = 30\n");
    EXPECT_EQ(live("--grab-timeout 2"), 4) << out << err;
    // The device sends 30 frames; OpenNI2 keeps only a stream's newest frame, so a reader that
    // was late (a loaded machine) may have missed one: every frame read is mapped.
    const uint64_t got = number(err, R"(camera lost: the camera was disconnected after (\d+) frames)");
    EXPECT_LE(got, 30u);
    EXPECT_GE(got, 25u);
    EXPECT_EQ(number(out, R"(frames mapped\s+: (\d+))"), got);
    EXPECT_TRUE(fs::exists(dir / "live" / "index.json"));
    EXPECT_TRUE(fs::exists(dir / "live" / "map_0000.pndt.gz"));
}

TEST_F(LiveCli, FramesWithoutPosesAreSkippedAndCounted)
{
    camera("");
    // The localiser stops after 0.5 s of poses (15 of them): later frames wait 0.1 s in vain.
    ASSERT_EQ(live("--max-frames 45 --pose-wait 0.1", "--rate 0 --max-poses 15"), 0) << out << err;
    const uint64_t skipped = number(out, R"(frames skipped\s+: (\d+) waited)");
    const uint64_t mapped = number(out, R"(frames mapped\s+: (\d+))");
    EXPECT_EQ(mapped + skipped, 45u) << out;
    EXPECT_LE(mapped, 15u);
    EXPECT_GE(skipped, 30u);
}

TEST_F(LiveCli, AWrongOrCorruptModelFileIsNamed)
{
    camera("");
    EXPECT_EQ(sh(fmt::format("cd {} && {} --pose-tcp {} --model missing_model.json > o.txt 2> e.txt", dir.string(),
                             PNDT_LIVE_EXE, port)),
              1);
    EXPECT_NE(slurp(dir / "e.txt").find("missing_model.json"), std::string::npos) << slurp(dir / "e.txt");
    std::ofstream(dir / "corrupt.json") << "{ \"format\": \"pndt-segmentation-model/1\", \"kind\": ";
    EXPECT_EQ(sh(fmt::format("cd {} && {} --pose-tcp {} --model corrupt.json > o.txt 2> e.txt", dir.string(),
                             PNDT_LIVE_EXE, port)),
              1);
    EXPECT_NE(slurp(dir / "e.txt").find("corrupt.json"), std::string::npos) << slurp(dir / "e.txt");
}

TEST_F(LiveCli, SigtermFinalisesAndWritesTheCurrentMap)
{
    camera("");
    const std::string cmd = fmt::format(
        "cd {0} && (PNDT_VIRTUAL_CAMERA={0}/camera.cfg LD_LIBRARY_PATH={1} {2} --pose-tcp {3} --pose-format tum "
        "--period 0 -o {0}/live > live.out 2> live.err & pid=$!; echo $pid > live.pid; wait $pid; echo $? > live.rc) & "
        "{4} {0}/poses.txt --to 127.0.0.1:{3} --rate 0 > send.out 2>&1; sleep 2; kill -TERM $(cat {0}/live.pid); wait",
        dir.string(), PNDT_ONI_DIR, PNDT_LIVE_EXE, port, PNDT_POSE_SEND_EXE);
    sh(cmd);
    out = slurp(dir / "live.out");
    EXPECT_EQ(std::stoi(slurp(dir / "live.rc")), 0) << out << slurp(dir / "live.err");
    EXPECT_NE(out.find("stopped; the current map was finalised and written"), std::string::npos) << out;
    const uint64_t mapped = number(out, R"(frames mapped\s+: (\d+))");
    EXPECT_GE(mapped, 20u);  // about 2 s at 30 Hz
    EXPECT_TRUE(fs::exists(dir / "live" / "map_0000.pndt.gz"));
    EXPECT_NE(slurp(dir / "live" / "index.json").find(fmt::format("\"frames\": {}", mapped)), std::string::npos);
}
