// A path on the navigation grid with MRPT's own planner (PlannerSimple2D).
#pragma once

#include <Eigen/Core>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>

#include <string>
#include <vector>

namespace pndt::nav
{
struct PlannedPath
{
    bool found = false;
    std::vector<mrpt::math::TPoint2D> points;  ///< start ... goal, world frame
    double length = 0;                         ///< metres along the points
    double seconds = 0;                        ///< planning time
    std::string reason;
};

/// PlannerSimple2D with `robot_radius` (it grows the obstacles itself; unknown
/// cells count as obstacles: only cells with free probability > 0.5 are free).
PlannedPath planPath(const mrpt::maps::COccupancyGridMap2D& grid, const Eigen::Vector2d& start,
                     const Eigen::Vector2d& goal, double robot_radius, double min_step = 0.2);

/// MRPT's TP-Space RRT planner (PlannerRRT_SE2_TPS): paths the robot's
/// kinematics can follow, ending at the goal's heading (within goal_angle).
struct TpsPlannerOptions
{
    double robot_radius = 0.3;     ///< the robot as an octagon around this circle
    double time_limit = 3.0;       ///< seconds of search
    double goal_distance = 0.15;   ///< accepted distance to the goal (m)
    double goal_angle = 0.35;      ///< accepted heading error at the goal (rad)
    std::string ptg_section = "CReactiveNavigationSystem";  ///< where PTG_COUNT, PTG0_... are
    std::string ptg_cache_dir;     ///< empty = <temp>/pndt-nav-ptg-cache
};
/// Obstacles are `obstacles` (world frame, e.g. getAsSimplePointsMap()); poses
/// are sampled inside the grid's extent. Deterministic for a given MRPT random seed.
PlannedPath planPathTPS(const mrpt::maps::CSimplePointsMap& obstacles, const mrpt::maps::COccupancyGridMap2D& grid,
                        const mrpt::math::TPose2D& start, const mrpt::math::TPose2D& goal,
                        const mrpt::config::CConfigFileBase& ptg_config, const TpsPlannerOptions& options);

}  // namespace pndt::nav
