// A path on the navigation grid with MRPT's own planner (PlannerSimple2D).
#pragma once

#include <Eigen/Core>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/TPoint2D.h>

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

}  // namespace pndt::nav
