// A simulated robot driven by MRPT's reactive navigator (reactive_drive.h).
#include <mrpt/kinematics/CVehicleSimul_DiffDriven.h>
#include <mrpt/kinematics/CVehicleVelCmd_DiffDriven.h>
#include <mrpt/nav/reactive/CReactiveNavigationSystem.h>
#include <mrpt/nav/reactive/CRobot2NavInterfaceForSimulator.h>
#include <mrpt/system/datetime.h>
#include <pndt/nav/reactive_drive.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

namespace pndt::nav
{
namespace
{
/// The simulator's robot, with obstacles from the map around its true pose.
class MapSensingRobot : public mrpt::nav::CRobot2NavInterfaceForSimulator_DiffDriven
{
   public:
    MapSensingRobot(mrpt::kinematics::CVehicleSimul_DiffDriven& sim, const PanopticNDTMap& map, double range)
        : CRobot2NavInterfaceForSimulator_DiffDriven(sim), sim_(sim), map_(map), range_(range)
    {
    }
    bool senseObstacles(mrpt::maps::CSimplePointsMap& obstacles, mrpt::system::TTimeStamp& timestamp) override
    {
        const mrpt::math::TPose2D p = sim_.getCurrentGTPose();
        obstaclePointsAround(map_.core(), map_.navigationOptions.obstacles, mrpt::poses::CPose3D(p.x, p.y, 0, p.phi, 0, 0),
                             range_, obstacles);
        timestamp = mrpt::system::now();
        return true;
    }
    // Quiet: the app reports what happened.
    void sendNavigationStartEvent() override {}
    void sendNavigationEndEvent() override {}
    void sendWaypointReachedEvent(int, bool) override {}
    void sendNewWaypointTargetEvent(int) override {}
    void sendNavigationEndDueToErrorEvent() override {}
    void sendWaySeemsBlockedEvent() override {}
    void sendApparentCollisionEvent() override {}
    void sendCannotGetCloserToBlockedTargetEvent() override {}

   private:
    mrpt::kinematics::CVehicleSimul_DiffDriven& sim_;
    const PanopticNDTMap& map_;
    double range_;
};

/// The navigator without its INFO chatter (watchdog notes, timing report at exit).
class QuietNavigator : public mrpt::nav::CReactiveNavigationSystem
{
   public:
    explicit QuietNavigator(mrpt::nav::CRobot2NavInterface& robot) : CReactiveNavigationSystem(robot, false, false)
    {
        setMinLoggingLevel(mrpt::system::LVL_ERROR);
        m_timlog_delays.enable(false);
        m_timlog_delays.setMinLoggingLevel(mrpt::system::LVL_ERROR);
    }
};

const char* stateName(mrpt::nav::CAbstractNavigator::TState s)
{
    using N = mrpt::nav::CAbstractNavigator;
    return s == N::IDLE ? "idle" : s == N::NAVIGATING ? "navigating" : s == N::SUSPENDED ? "suspended" : "error";
}

/// Distance from the robot centre to the nearest obstacle point in the map's band.
double nearestObstacle(const mrpt::maps::CSimplePointsMap& obstacles, const mrpt::math::TPose2D& p)
{
    if (obstacles.empty()) return std::numeric_limits<double>::infinity();
    return std::sqrt(obstacles.squareDistanceToClosestCorrespondence(float(p.x), float(p.y)));
}
}  // namespace

DriveResult driveReactive(const PanopticNDTMap& map, const mrpt::config::CConfigFileBase& nav_config,
                          const mrpt::math::TPose2D& start, const std::vector<mrpt::math::TPoint2D>& waypoints,
                          double goal_yaw, const DriveOptions& o)
{
    DriveResult r;
    if (waypoints.empty())
    {
        r.state = "no waypoints";
        return r;
    }
    mrpt::kinematics::CVehicleSimul_DiffDriven sim;
    sim.setCurrentGTPose(start);
    MapSensingRobot robot(sim, map, o.sense_range);
    robot.setMinLoggingLevel(mrpt::system::LVL_ERROR);
    QuietNavigator nav(robot);
    if (!o.log_dir.empty())
    {
        std::filesystem::create_directories(o.log_dir);
        nav.setLogFileDirectory(o.log_dir);
        nav.enableLogFile(true);
    }
    nav.loadConfigFile(nav_config);
    const std::string cache = o.ptg_cache_dir.empty()
                                  ? (std::filesystem::temp_directory_path() / "pndt-nav-ptg-cache").string()
                                  : o.ptg_cache_dir;
    std::filesystem::create_directories(cache);
    nav.params_abstract_ptg_navigator.ptg_cache_files_directory = cache;
    nav.initialize();

    mrpt::nav::TWaypointSequence seq;
    for (size_t i = 0; i < waypoints.size(); ++i)
    {
        const bool last = i + 1 == waypoints.size();
        seq.waypoints.emplace_back(waypoints[i].x, waypoints[i].y, last ? o.goal_tolerance : 0.3, !last);
    }
    nav.navigateWaypoints(seq);

    const mrpt::maps::CSimplePointsMap& all_obstacles = *map.getAsSimplePointsMap();
    r.min_obstacle_distance = std::numeric_limits<double>::infinity();
    const int steps = int(o.time_limit / o.time_step);
    for (int k = 0; k < steps; ++k)
    {
        nav.navigationStep();
        sim.simulateOneTimeStep(o.time_step);
        const mrpt::math::TPose2D p = sim.getCurrentGTPose();
        r.trajectory.push_back(p);
        r.min_obstacle_distance = std::min(r.min_obstacle_distance, nearestObstacle(all_obstacles, p));
        if (nav.getCurrentState() != mrpt::nav::CAbstractNavigator::NAVIGATING) break;
    }
    r.state = stateName(nav.getCurrentState());
    if (nav.getCurrentState() == mrpt::nav::CAbstractNavigator::NAV_ERROR) r.state += ": " + nav.getErrorReason().error_msg;
    const mrpt::math::TPoint2D goal = waypoints.back();
    // Face the object: turn in place (the navigator drives to points, not headings).
    mrpt::kinematics::CVehicleVelCmd_DiffDriven cmd;
    for (int k = 0; k < 200; ++k)
    {
        const double err = std::remainder(goal_yaw - sim.getCurrentGTPose().phi, 2 * M_PI);
        if (std::abs(err) < 0.02) break;
        cmd.lin_vel = 0;
        cmd.ang_vel = std::clamp(2.0 * err, -1.0, 1.0);
        sim.sendVelCmd(cmd);
        sim.simulateOneTimeStep(o.time_step);
        r.trajectory.push_back(sim.getCurrentGTPose());
    }
    cmd.setToStop();
    sim.sendVelCmd(cmd);
    const mrpt::math::TPose2D end = sim.getCurrentGTPose();
    r.seconds = sim.getTime();
    r.final_distance = std::hypot(end.x - goal.x, end.y - goal.y);
    r.final_heading_error = std::abs(std::remainder(goal_yaw - end.phi, 2 * M_PI));
    r.reached = nav.getCurrentState() == mrpt::nav::CAbstractNavigator::IDLE && r.final_distance <= o.goal_tolerance + 0.1;
    return r;
}

}  // namespace pndt::nav
