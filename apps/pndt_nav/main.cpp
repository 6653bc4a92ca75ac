// pndt-nav: a map in, a robot's errand out. Loads a map (a .pndt.gz, or the
// newest in a pndt-map output folder), projects it to a 2D grid, answers a query
// ("table with most chairs"), picks a goal pose next to the answer, plans a path
// with MRPT's PlannerSimple2D and, with --simulate, drives a simulated robot
// there with MRPT's reactive navigator. Writes result.json, grid.png,
// grid.gridmap.gz (the COccupancyGridMap2D) and the navigator's logs.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/random/RandomGenerators.h>
#include <pndt/app/cli_numbers.h>
#include <pndt/app/map_config.h>
#include <pndt/io/atomic_file.h>
#include <pndt/mrpt/map_files.h>
#include <pndt/nav/grid_image.h>
#include <pndt/nav/map_source.h>
#include <pndt/nav/nav_json.h>
#include <pndt/nav/reactive_drive.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

using namespace pndt;
using namespace pndt::nav;
namespace fs = std::filesystem;

namespace
{
struct Settings
{
    std::string map;
    std::string query;
    std::string out = "nav_out";
    std::vector<double> start;  // x y [yaw]
    double robot_radius = 0.3;
    double resolution = 0;
    std::vector<double> band{0.05, 1.8};
    std::vector<std::string> exclude{"floor", "ceiling"};
    bool simulate = false;
    std::string planner = "simple";
    // $PNDT_CONFIG_DIR, the installed share/panopticndt/config, else the source tree's.
    std::string nav_config = pndt::app::configDir(PNDT_CONFIG_DIR) + "/reactive2d.ini";
    double wait_for_map = 0;
    double watch = 0;
    bool quiet = false;
};

std::vector<mrpt::math::TPoint2D> waypointsOf(const PlannedPath& path)
{
    return {path.points.begin() + 1, path.points.end()};  // the start is where the robot is
}

/// The map, waiting up to --wait-for-map seconds for pndt-map's first one.
LoadedMap firstMap(const Settings& s)
{
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(s.wait_for_map);
    for (;;)
    {
        try
        {
            return loadNavigationMap(s.map);
        }
        catch (const InputError&)
        {
            if (std::chrono::steady_clock::now() >= deadline) throw;
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
        }
    }
}

/// The reactive navigator's settings (also the TP-Space planner's PTGs).
mrpt::config::CConfigFileMemory navigatorConfig(const Settings& s)
{
    std::ifstream in(s.nav_config);
    if (!in) throw InputError(fmt::format("{}: navigator config not found", s.nav_config));
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return mrpt::config::CConfigFileMemory(text);
}

nlohmann::json run(const Settings& s, LoadedMap& loaded)
{
    nlohmann::json result;
    PanopticNDTMap& map = *loaded.map;
    map.navigationOptions.obstacles.min_height = s.band.at(0);
    map.navigationOptions.obstacles.max_height = s.band.at(1);
    map.navigationOptions.obstacles.excluded_classes = s.exclude;
    result["map"] = {{"file", loaded.file.string()}, {"description", map.asString()}};

    GridOptions go;
    go.resolution = s.resolution;
    go.obstacles = map.navigationOptions.obstacles;
    const NavigationGrid grid = buildNavigationGrid(map.core(), go);
    result["grid"] = toJson(grid);
    const std::vector<MapObject> objects = mapObjects(map.core(), loaded.file.filename().string(), 5);
    result["objects"] = toJson(objects);

    GoalPose goal;
    PlannedPath path;
    DriveResult drive;
    const MapObject* target = nullptr;
    if (!s.query.empty())
    {
        const QueryResult q = runQuery(objects, map.core().options().classes, s.query);
        result["query"] = toJson(q);
        if (!s.quiet) std::cout << "query: " << q.summary << "\n";
        target = q.best();
        if (!target) throw InputError(fmt::format("nothing in the map answers '{}': {}", s.query, q.summary));
        GoalOptions o;
        o.robot_radius = s.robot_radius;
        o.keep_clear_classes = defaultKeepClearClasses(map.core().options().classes);
        if (s.start.size() >= 2) o.start = Eigen::Vector2d(s.start[0], s.start[1]);
        goal = goalNextTo(*target, objects, grid.grid, o);
        result["goal"] = toJson(goal);
        if (!goal.found) throw InputError(goal.reason);
        if (!s.quiet)
            std::cout << fmt::format("goal: ({:.2f}, {:.2f}) facing {:.0f} deg, {:.2f} m from {} {}, clearance {:.2f} m\n",
                                     goal.x, goal.y, goal.yaw * 180 / M_PI, goal.distance_to_object, target->class_name,
                                     target->id, goal.clearance);
        if (o.start)
        {
            const double yaw0 = s.start.size() >= 3 ? s.start[2] : 0;
            if (s.planner == "tps")
            {
                TpsPlannerOptions t;
                t.robot_radius = s.robot_radius;
                path = planPathTPS(*map.getAsSimplePointsMap(), grid.grid, {s.start[0], s.start[1], yaw0},
                                   {goal.x, goal.y, goal.yaw}, navigatorConfig(s), t);
            }
            else
                path = planPath(grid.grid, *o.start, {goal.x, goal.y}, s.robot_radius);
            nlohmann::json pj = {{"planner", s.planner == "tps" ? "PlannerRRT_SE2_TPS" : "PlannerSimple2D"},
                                 {"found", path.found},
                                 {"length", path.length},
                                 {"planning_ms", path.seconds * 1000}};
            nlohmann::json pts = nlohmann::json::array();
            for (const auto& p : path.points) pts.push_back({p.x, p.y});
            pj["points"] = pts;
            if (!path.found) pj["reason"] = path.reason;
            result["path"] = pj;
            if (!s.quiet)
                std::cout << (path.found ? fmt::format("path: {} points, {:.2f} m, planned in {:.2f} ms ({})\n",
                                                       path.points.size(), path.length, path.seconds * 1000,
                                                       s.planner == "tps" ? "PlannerRRT_SE2_TPS" : "PlannerSimple2D")
                                         : "path: " + path.reason + "\n");
        }
        if (s.simulate)
        {
            if (!path.found)
                throw InputError(s.start.empty() ? "--simulate needs --start x,y[,yaw] (where the robot starts)"
                                                 : "--simulate needs a path to the goal: " + path.reason);
            mrpt::config::CConfigFileMemory cfg = navigatorConfig(s);
            // The differential-drive PTGs check collisions with a polygon: an octagon around the disc.
            std::string xs, ys;
            for (int k = 0; k < 8; ++k)
            {
                const double a = (k + 0.5) * M_PI / 4, r = s.robot_radius / std::cos(M_PI / 8);
                xs += fmt::format("{:.4f} ", r * std::cos(a));
                ys += fmt::format("{:.4f} ", r * std::sin(a));
            }
            cfg.write("CReactiveNavigationSystem", "RobotModel_circular_shape_radius", s.robot_radius);
            cfg.write("CReactiveNavigationSystem", "RobotModel_shape2D_xs", xs);
            cfg.write("CReactiveNavigationSystem", "RobotModel_shape2D_ys", ys);
            DriveOptions d;
            d.robot_radius = s.robot_radius;
            d.log_dir = (fs::path(s.out) / "navlog").string();
            const double start_yaw = s.start.size() >= 3 ? s.start[2] : 0;
            drive = driveReactive(map, cfg, {s.start[0], s.start[1], start_yaw}, waypointsOf(path), goal.yaw, d);
            nlohmann::json traj = nlohmann::json::array();
            for (const auto& p : drive.trajectory) traj.push_back({p.x, p.y, p.phi});
            result["simulation"] = {{"reached", drive.reached},
                                    {"seconds", drive.seconds},
                                    {"final_distance", drive.final_distance},
                                    {"final_heading_error", drive.final_heading_error},
                                    {"min_obstacle_distance", drive.min_obstacle_distance},
                                    {"navigator_state", drive.state},
                                    {"navlog_dir", d.log_dir},
                                    {"trajectory", traj}};
            if (!s.quiet)
                std::cout << fmt::format("simulation: {} in {:.1f} s, {:.2f} m from the goal, nearest obstacle {:.2f} m "
                                         "from the robot centre (navigator: {})\n",
                                         drive.reached ? "reached" : "NOT reached", drive.seconds, drive.final_distance,
                                         drive.min_obstacle_distance, drive.state);
        }
    }
    fs::create_directories(s.out);
    GridPicture pic;
    pic.grid = &grid;
    pic.objects = &objects;
    pic.highlight_id = target ? target->id : 0;
    pic.goal = goal.found ? &goal : nullptr;
    pic.path = path.found ? &path : nullptr;
    for (const auto& p : drive.trajectory) pic.trajectory.emplace_back(p.x, p.y);
    writeGridPicture(pic, (fs::path(s.out) / "grid.png").string());
    saveArchive(grid.grid, (fs::path(s.out) / "grid.gridmap.gz").string());
    return result;
}
}  // namespace

int main(int argc, char** argv)
{
    Settings s;
    CLI::App app{"pndt-nav: grid, object query, goal pose and path on a PanopticNDT map"};
    app.add_option("map", s.map, "a .pndt.gz map, or a pndt-map output folder (its newest map)")->required();
    app.add_option("-q,--query", s.query, "e.g. \"table with most chairs\", \"a table with 8 chairs\", \"chair nearest to 1 2\"");
    app.add_option("--start", s.start, "robot start x,y[,yaw] (m, rad): reachability, path and simulation start")
        ->delimiter(',')
        ->expected(2, 3)
        ->type_name("X,Y[,YAW]");
    app.add_option("--robot-radius", s.robot_radius, "m")->check(app::kPositive);
    app.add_option("--resolution", s.resolution, "grid cell size in m (0 = the map's voxel size)")->check(app::kNonNegative);
    app.add_option("--band", s.band, "obstacle heights above the floor: min,max (m)")->delimiter(',')->expected(2);
    app.add_option("--exclude", s.exclude, "classes that are never obstacles")->delimiter(',');
    app.add_option("--planner", s.planner, "simple: PlannerSimple2D on the grid; tps: PlannerRRT_SE2_TPS (TP-Space RRT) on the obstacle points")
        ->check(CLI::IsMember({"simple", "tps"}));
    app.add_flag("--simulate", s.simulate, "drive a simulated robot there with MRPT's reactive navigator");
    app.add_option("--nav-config", s.nav_config, "reactive navigator .ini")->capture_default_str();
    app.add_option("--wait-for-map", s.wait_for_map, "seconds to wait for a map to appear in the folder");
    app.add_option("--watch", s.watch,
                   "folder source: for this many seconds, answer again whenever pndt-map writes a newer map");
    app.add_option("-o,--out", s.out, "output folder");
    app.add_flag("--quiet", s.quiet, "no summary on stdout");
    CLI11_PARSE(app, argc, argv);
    // CLI11's number checks let NaN and infinity through.
    const auto finite = [](const std::vector<double>& v) {
        return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
    };
    if (!finite(s.start) || !finite(s.band) || !std::isfinite(s.robot_radius) || !std::isfinite(s.resolution))
    {
        std::cerr << "pndt-nav: --start, --band, --robot-radius and --resolution take finite numbers\n";
        return 1;
    }
    try
    {
        mrpt::random::getRandomGenerator().randomize(1);  // the TP-Space RRT samples: same answer every run
        LoadedMap loaded = firstMap(s);
        auto answer = [&] {
            const nlohmann::json result = run(s, loaded);
            const fs::path json_path = fs::path(s.out) / "result.json";
            io::writeFileAtomically(json_path.string(), result.dump(2) + "\n");  // never half a file; errors named
            if (!s.quiet) std::cout << "wrote " << json_path.string() << ", grid.png, grid.gridmap.gz in " << s.out << "\n";
        };
        answer();
        // Short-term maps replace each other: follow the newest one.
        const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(s.watch);
        while (std::chrono::steady_clock::now() < until)
        {
            std::this_thread::sleep_for(std::chrono::milliseconds(250));
            if (!reloadIfNewer(s.map, loaded)) continue;
            if (!s.quiet) std::cout << "new map: " << loaded.file.string() << "\n";
            answer();
        }
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "pndt-nav: " << e.what() << "\n";
        return 1;
    }
}
