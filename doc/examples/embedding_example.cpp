// Embedding PanopticNDT in an MRPT navigation app: the code a user copies.
// (doc/pndt-nav.md walks through it; built by tests/nav/CMakeLists.txt and run as the test
// nav_embedding_example.)
//
//  1. the map comes from an .ini through CMultiMetricMap, like any MRPT map;
//  2. observations go in as MRPT observations: a CObservation3DRangeScan and its two
//     panoptic CObservationImages per frame, with the robot pose from the localiser;
//  3. the navigator asks for obstacles around the robot, a 2D grid for the planner,
//     and objects ("the table with the most chairs") and a goal next to one.
// Here the observations come from a generated room (pndt::sim: a table with six chairs)
// instead of a camera. Only installed headers: it builds against find_package(PanopticNDT)
// with PanopticNDT::nav and PanopticNDT::sim.
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <pndt/look_at.h>
#include <pndt/mrpt/PanopticNDTMap.h>
#include <pndt/mrpt/observation_frame.h>
#include <pndt/nav/goal_pose.h>
#include <pndt/nav/navigation_grid.h>
#include <pndt/nav/object_query.h>
#include <pndt/nav/path_planning.h>
#include <pndt/sim/furniture.h>
#include <pndt/sim/renderer.h>
#include <pndt/sim/trajectory.h>

#include <cmath>
#include <iostream>

namespace
{
/// A 8 x 6 m room with a table and six chairs around it: what the camera would see.
pndt::sim::Scene room()
{
    pndt::sim::Scene s;
    s.room = Eigen::AlignedBox3d(Eigen::Vector3d(-4, -3, 0), Eigen::Vector3d(4, 3, 2.6));
    const Eigen::Vector2d table(-1.83, 0.04);
    pndt::sim::addTable(s, {Eigen::Vector3d(table.x(), table.y(), 0), 0}, 1, Eigen::Vector3d(1.6, 0.9, 0.75));
    uint32_t id = 2;
    for (const Eigen::Vector2d& d : {Eigen::Vector2d(-0.4, 0.8), Eigen::Vector2d(0.4, 0.8), Eigen::Vector2d(-0.4, -0.8),
                                     Eigen::Vector2d(0.4, -0.8), Eigen::Vector2d(1.15, 0), Eigen::Vector2d(-1.15, 0)})
        pndt::sim::addChair(s, {Eigen::Vector3d(table.x() + d.x(), table.y() + d.y(), 0), std::atan2(-d.y(), -d.x())},
                            id++);  // facing the table
    return s;
}

/// Around the table looking down at it, then from the middle of the room outwards.
std::vector<pndt::Pose> cameraPoses()
{
    std::vector<pndt::Pose> poses = pndt::sim::orbit({-1.83, 0.04, 0}, 2.0, 1.6, 0.3, 16);
    for (int k = 0; k < 12; ++k)
    {
        const double a = 2 * M_PI * k / 12;
        const Eigen::Vector3d eye(0.2, -0.1, 1.4);
        poses.push_back(pndt::lookAt(eye, eye + Eigen::Vector3d(3 * std::cos(a), 3 * std::sin(a), -1.3)));
    }
    return poses;
}
}  // namespace

int main()
{
    // 1. The map, from an .ini (the plugin is linked, so the class is registered).
    mrpt::config::CConfigFileMemory ini(R"ini(
[MAP]
PanopticNDTMap_count=1
[MAP_PanopticNDTMap_00_creationOpts]
voxel_size=0.10
)ini");
    mrpt::maps::TSetOfMetricMapInitializers defs;
    defs.loadFromConfigFile(ini, "MAP");
    mrpt::maps::CMultiMetricMap maps;
    maps.setListOfMaps(defs);
    auto map = maps.mapByClass<pndt::PanopticNDTMap>();
    if (!map) return std::cerr << "no PanopticNDTMap: is the plugin loaded?\n", 1;

    // 2. Observations with the robot's pose (here the camera is the robot).
    double t = 0;
    const pndt::sim::Scene scene = room();
    for (const pndt::Pose& T_world_cam : cameraPoses())
    {
        // Your camera and segmentation network (here a perfect one on the generated room).
        const pndt::PanopticFrame frame =
            pndt::sim::renderPanopticFrame(scene, T_world_cam, {240, 180, 120.0, 120.0, 119.5, 89.5});
        const mrpt::poses::CPose3D robot = pndt::mrptSensorPoseOf(T_world_cam);    // your localiser
        mrpt::obs::CObservation3DRangeScan scan;
        pndt::rangeScanFrom(frame, scan);
        scan.sensorLabel = "RGBD";
        scan.timestamp = mrpt::Clock::fromDouble(1.7e9 + t);
        mrpt::obs::CObservationImage semantic, instance;
        pndt::labelImagesFrom(frame, "RGBD", scan.timestamp, semantic, instance);
        maps.insertObservation(scan, robot);
        maps.insertObservation(semantic, robot);
        maps.insertObservation(instance, robot);
        t += 0.2;
    }
    map->flushPending();

    // 3a. Obstacles for a reactive navigator: points around the robot, robot frame
    //     (CRobot2NavInterface::senseObstacles); or all of them, world frame.
    const mrpt::poses::CPose3D robot(0.1, -2.2, 0, M_PI / 2, 0, 0);
    mrpt::maps::CSimplePointsMap near_robot;
    pndt::obstaclePointsAround(map->core(), map->navigationOptions.obstacles, robot, 3.0, near_robot);
    const mrpt::maps::CSimplePointsMap* all_obstacles = map->getAsSimplePointsMap();

    // 3b. A grid for MRPT's planners.
    const pndt::nav::NavigationGrid grid = pndt::nav::buildNavigationGrid(map->core());

    // 3c. Objects, a question, a goal next to the answer and a path there.
    const auto objects = pndt::nav::mapObjects(map->core());
    const pndt::nav::QueryResult answer =
        pndt::nav::runQuery(objects, map->core().options().classes, "the table with the most chairs");
    if (!answer.best()) return std::cerr << answer.summary << "\n", 1;
    pndt::nav::GoalOptions goal_options;
    goal_options.start = Eigen::Vector2d(robot.x(), robot.y());
    goal_options.keep_clear_classes = pndt::nav::defaultKeepClearClasses(map->core().options().classes);
    const pndt::nav::GoalPose goal = pndt::nav::goalNextTo(*answer.best(), objects, grid.grid, goal_options);
    if (!goal.found) return std::cerr << goal.reason << "\n", 1;
    const pndt::nav::PlannedPath path =
        pndt::nav::planPath(grid.grid, *goal_options.start, {goal.x, goal.y}, goal_options.robot_radius);

    std::cout << map->asString() << "\n"
              << near_robot.size() << " obstacle points within 3 m of the robot, " << all_obstacles->size()
              << " in all\n"
              << "grid " << grid.grid.getSizeX() << " x " << grid.grid.getSizeY() << ": " << grid.free_cells
              << " free, " << grid.occupied_cells << " occupied, " << grid.unknown_cells << " unknown cells\n"
              << answer.summary << "\n"
              << "goal (" << goal.x << ", " << goal.y << "), path " << (path.found ? "found" : path.reason) << ", "
              << path.length << " m\n";
    return path.found && answer.matches[0].related.size() == 6 ? 0 : 1;
}
