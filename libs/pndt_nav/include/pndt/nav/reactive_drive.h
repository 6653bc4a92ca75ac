// Drives a simulated differential-drive robot (MRPT's CVehicleSimul_DiffDriven)
// along waypoints with MRPT's reactive navigator (CReactiveNavigationSystem),
// sensing obstacles from the map (obstaclePointsAround): the navigator never
// sees the map, only points around the robot, as with a real sensor.
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/math/TPose2D.h>
#include <pndt/mrpt/PanopticNDTMap.h>

#include <string>
#include <vector>

namespace pndt::nav
{
struct DriveOptions
{
    double robot_radius = 0.3;
    double sense_range = 3.0;       ///< obstacle points within this of the robot (m)
    double time_step = 0.1;         ///< simulation step (s)
    double time_limit = 120;        ///< simulated seconds
    double goal_tolerance = 0.20;   ///< final waypoint's allowed distance (m)
    std::string log_dir;            ///< navigator logs for navlog-viewer (empty = none)
    /// Where MRPT keeps its PTG look-up tables (seconds to build; reused when the
    /// PTG settings match). Empty = <temp>/pndt-nav-ptg-cache, never the working folder.
    std::string ptg_cache_dir;
};

struct DriveResult
{
    bool reached = false;
    double seconds = 0;                          ///< simulated time
    double final_distance = 0;                   ///< to the goal (m)
    double final_heading_error = 0;              ///< rad, after turning to face the object
    double min_obstacle_distance = 0;            ///< closest obstacle point to the robot centre on the way (m)
    std::vector<mrpt::math::TPose2D> trajectory; ///< one pose per step
    std::string state;                           ///< the navigator's last state / error
};

/// `waypoints`: the planned path without the start; the last one is the goal,
/// where the robot turns in place to `goal_yaw`.
DriveResult driveReactive(const PanopticNDTMap& map, const mrpt::config::CConfigFileBase& nav_config,
                          const mrpt::math::TPose2D& start, const std::vector<mrpt::math::TPoint2D>& waypoints,
                          double goal_yaw, const DriveOptions& options);

}  // namespace pndt::nav
