// pndt-nav end to end on the two-table room's map file: the query finds table A,
// the goal and MRPT's path are found, the simulated robot driven by MRPT's
// reactive navigator gets there without touching the true furniture; a folder
// source takes its newest map; bad input gives a clear message and exit code 1.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "nav_test_scene.h"

namespace fs = std::filesystem;

namespace
{
struct RunResult
{
    int code = -1;
    std::string out;
};

RunResult runShell(const std::string& command)
{
    RunResult r;
    FILE* p = ::popen((command + " 2>&1").c_str(), "r");
    if (!p) return r;
    std::array<char, 4096> buf;
    while (fgets(buf.data(), int(buf.size()), p)) r.out += buf.data();
    const int status = ::pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

RunResult run(const std::string& args) { return runShell(std::string(PNDT_NAV_EXE) + " " + args); }

fs::path tempDir(const std::string& name)
{
    const fs::path d = fs::temp_directory_path() / ("pndt_nav_cli_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

nlohmann::json readJson(const fs::path& p)
{
    std::ifstream in(p);
    return nlohmann::json::parse(in);
}

double truthClearance(double x, double y)
{
    double d = std::min(navtest::kRoomHalfX - std::abs(x), navtest::kRoomHalfY - std::abs(y));
    for (const navtest::ObjectTruth& t : navtest::truth())
    {
        const Eigen::Vector2d q = (Eigen::Vector2d(x, y) - t.xy).cwiseAbs() - t.half;
        d = std::min(d, q.cwiseMax(0.0).norm());
    }
    return d;
}
}  // namespace

TEST(PndtNavCli, TableWithMostChairsGoalPathAndSimulatedDrive)
{
    const fs::path out = tempDir("drive");
    const RunResult r = run(navtest::savedMapPath() + " --query 'table with most chairs' --start 3.3,-2.4,3.14 --simulate --out " +
                            out.string());
    std::cout << r.out;
    ASSERT_EQ(r.code, 0) << r.out;
    const nlohmann::json j = readJson(out / "result.json");
    // The answer is table A (six chairs).
    const uint32_t best = j["query"]["best"];
    bool is_table_a = false;
    for (const auto& o : j["objects"])
        if (o["id"] == best)
            is_table_a = std::hypot(double(o["centroid"][0]) - navtest::kTableA.x(), double(o["centroid"][1]) - navtest::kTableA.y()) < 0.2;
    EXPECT_TRUE(is_table_a);
    EXPECT_EQ(j["query"]["matches"][0]["count"], 6);
    ASSERT_TRUE(j["goal"]["found"]);
    ASSERT_TRUE(j["path"]["found"]);
    const auto& sim = j["simulation"];
    EXPECT_TRUE(sim["reached"]) << sim["navigator_state"];
    EXPECT_LT(double(sim["final_distance"]), 0.25);
    EXPECT_LT(double(sim["final_heading_error"]), 0.05);
    // The robot's disc never touches the true furniture or walls.
    double closest = 1e9;
    for (const auto& p : sim["trajectory"]) closest = std::min(closest, truthClearance(p[0], p[1]));
    std::cout << "  closest approach to true furniture/walls: " << closest << " m (robot radius 0.3)\n";
    EXPECT_GE(closest, 0.3);
    EXPECT_TRUE(fs::exists(out / "grid.png"));
    EXPECT_TRUE(fs::exists(out / "grid.gridmap.gz"));
    bool navlog = false;
    for (const auto& e : fs::directory_iterator(out / "navlog")) navlog |= e.path().extension() == ".reactivenavlog";
    EXPECT_TRUE(navlog) << "no navigator log for navlog-viewer";
    fs::remove_all(out);
}

TEST(PndtNavCli, TpSpacePlannerOnTheObstaclePoints)
{
    const fs::path out = tempDir("tps");
    const RunResult r = run(navtest::savedMapPath() + " --query 'table with most chairs' --start 0.1,-2.2,1.57 --planner tps --out " +
                            out.string());
    ASSERT_EQ(r.code, 0) << r.out;
    const nlohmann::json j = readJson(out / "result.json");
    EXPECT_EQ(j["path"]["planner"], "PlannerRRT_SE2_TPS");
    ASSERT_TRUE(j["path"]["found"]) << j["path"];
    const auto& pts = j["path"]["points"];
    EXPECT_NEAR(double(pts.back()[0]), double(j["goal"]["pose"][0]), 0.16);
    EXPECT_NEAR(double(pts.back()[1]), double(j["goal"]["pose"][1]), 0.16);
    fs::remove_all(out);
}

TEST(PndtNavCli, AFolderSourceTakesItsNewestMap)
{
    const fs::path dir = tempDir("folder"), out = dir / "out";
    fs::copy_file(navtest::savedMapPath(), dir / "map_0000.pndt.gz");
    fs::copy_file(navtest::savedMapPath(), dir / "map_0001.pndt.gz");
    fs::last_write_time(dir / "map_0000.pndt.gz", fs::last_write_time(dir / "map_0001.pndt.gz") - std::chrono::seconds(10));
    const RunResult r = run(dir.string() + " --query 'a table with three chairs' --quiet --out " + out.string());
    ASSERT_EQ(r.code, 0) << r.out;
    const nlohmann::json j = readJson(out / "result.json");
    EXPECT_EQ(fs::path(std::string(j["map"]["file"])).filename(), "map_0001.pndt.gz");
    EXPECT_EQ(j["query"]["matches"].size(), 1u);
    EXPECT_TRUE(j["goal"]["found"]);  // no start: the largest free region
    EXPECT_FALSE(j.contains("path"));
    fs::remove_all(dir);
}

TEST(PndtNavCli, WatchAnswersAgainWhenANewerMapAppears)
{
    const fs::path dir = tempDir("watch"), out = dir / "out";
    fs::copy_file(navtest::savedMapPath(), dir / "map_0000.pndt.gz");
    // pndt-map writes its next short-term map a second later (atomically, by rename).
    const std::string writer = "(sleep 1; cp " + navtest::savedMapPath() + " " + (dir / "tmp").string() + " && mv " +
                               (dir / "tmp").string() + " " + (dir / "map_0001.pndt.gz").string() + ") & ";
    const RunResult r = runShell(writer + std::string(PNDT_NAV_EXE) + " " + dir.string() +
                                 " --query 'table with most chairs' --watch 3 --out " + out.string());
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("new map: " + (dir / "map_0001.pndt.gz").string()), std::string::npos) << r.out;
    EXPECT_EQ(fs::path(std::string(readJson(out / "result.json")["map"]["file"])).filename(), "map_0001.pndt.gz");
    fs::remove_all(dir);
}

TEST(PndtNavCli, BadInputIsAClearMessage)
{
    const fs::path out = tempDir("errors");
    const std::string map = navtest::savedMapPath();
    struct Case
    {
        std::string args, message;
    };
    for (const Case& c : {Case{map + " --query 'sofa-bed with most cushions'", "no known class"},
                          Case{map + " --query 'a table with eight chairs'", "nothing in the map answers"},
                          Case{"/nonexistent/map.pndt.gz", "no such file"},
                          Case{out.string(), "no *.pndt.gz map"},
                          Case{map + " --query 'table with most chairs' --robot-radius 2.5", "no free, reachable pose"},
                          Case{map + " --query 'the unicorn with the most chairs'", "'unicorn' is not a class"},
                          Case{map + " --query 'table with most chairs' --start nan,nan", "take finite numbers"},
                          Case{map + " --query 'table with most chairs' --resolution nan", "--resolution: nan is not a number >= 0"},
                          // It said "give --start x,y" although a start was given.
                          Case{map + " --query 'table with most chairs' --start 100,100 --simulate",
                               "--simulate needs a path to the goal: the start (100.00, 100.00) is outside the grid"},
                          Case{map + " --query 'table with most chairs' --simulate", "--simulate needs --start x,y[,yaw]"}})
    {
        const RunResult r = run(c.args + " --out " + (out / "o").string());
        // Option values the command line's own checks refuse exit with CLI11's code (105).
        EXPECT_EQ(r.code, c.message.rfind("--resolution", 0) == 0 ? 105 : 1) << c.args << "\n" << r.out;
        EXPECT_NE(r.out.find(c.message), std::string::npos) << c.args << "\n" << r.out;
    }
    fs::remove_all(out);
}

TEST(PndtNavCli, AnAnswerThatCannotBeWrittenIsAnErrorNamingTheFile)
{
    // result.json was written with an unchecked ofstream: a full disk or a folder in its place
    // printed "wrote .../result.json" and exit 0 with nothing written, and a consumer following
    // --watch read half files (grid.png too).
    const fs::path out = tempDir("unwritable");
    const std::string map = navtest::savedMapPath();
    fs::create_directories(out / "a" / "result.json");  // a folder where the file goes
    RunResult r = run(map + " --query 'table with most chairs' --out " + (out / "a").string());
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("cannot write '" + (out / "a" / "result.json").string() + "'"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("wrote "), std::string::npos) << r.out;
    if (fs::exists("/dev/full"))
    {
        fs::create_directories(out / "b");
        fs::create_symlink("/dev/full", out / "b" / "grid.png");  // replaced by the rename, never written through
        r = run(map + " --query 'table with most chairs' --out " + (out / "b").string());
        EXPECT_EQ(r.code, 0) << r.out;
        EXPECT_FALSE(fs::is_symlink(out / "b" / "grid.png"));
        EXPECT_GT(fs::file_size(out / "b" / "grid.png"), 1000u);
        EXPECT_NO_THROW(readJson(out / "b" / "result.json"));
    }
    // Nothing under a temporary name is left behind.
    for (const auto& e : fs::recursive_directory_iterator(out))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
    fs::remove_all(out);
}
