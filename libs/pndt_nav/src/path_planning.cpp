// PlannerSimple2D wrapper (path_planning.h).
#include <fmt/format.h>
#include <mrpt/nav/planners/PlannerSimple2D.h>
#include <mrpt/poses/CPose2D.h>
#include <pndt/nav/path_planning.h>

#include <chrono>
#include <deque>
#include <utility>

namespace pndt::nav
{
PlannedPath planPath(const mrpt::maps::COccupancyGridMap2D& grid, const Eigen::Vector2d& start,
                     const Eigen::Vector2d& goal, double robot_radius, double min_step)
{
    PlannedPath out;
    if (!(robot_radius >= 0 && robot_radius < 10))
    {
        out.reason = fmt::format("the robot radius {} m is out of range (0-10 m)", robot_radius);
        return out;
    }
    // PlannerSimple2D indexes the grid at the start and goal cells without a bounds check
    // (ASan: a SEGV inside computePath for a goal outside the map): refused here, clearly.
    for (const auto& [what, p] : {std::pair{"start", start}, std::pair{"goal", goal}})
        if (!(p.x() >= grid.getXMin() && p.x() < grid.getXMax() && p.y() >= grid.getYMin() && p.y() < grid.getYMax()))
        {
            out.reason = fmt::format("the {} ({:.2f}, {:.2f}) is outside the grid ([{:.2f}, {:.2f}] x [{:.2f}, {:.2f}] m)",
                                     what, p.x(), p.y(), grid.getXMin(), grid.getXMax(), grid.getYMin(), grid.getYMax());
            return out;
        }
    mrpt::nav::PlannerSimple2D planner;
    planner.robotRadius = float(robot_radius);
    planner.minStepInReturnedPath = float(min_step);
    planner.occupancyThreshold = 0.5f;
    std::deque<mrpt::math::TPoint2D> path;
    bool not_found = true;
    const auto t0 = std::chrono::steady_clock::now();
    try
    {
        planner.computePath(grid, mrpt::poses::CPose2D(start.x(), start.y(), 0), mrpt::poses::CPose2D(goal.x(), goal.y(), 0),
                            path, not_found);
    }
    catch (const std::exception& e)
    {
        out.reason = fmt::format("PlannerSimple2D failed: {}", e.what());
        return out;
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (not_found || path.empty())
    {
        out.reason = fmt::format("PlannerSimple2D found no path from ({:.2f}, {:.2f}) to ({:.2f}, {:.2f}) for a robot "
                                 "of radius {:.2f} m",
                                 start.x(), start.y(), goal.x(), goal.y(), robot_radius);
        return out;
    }
    out.found = true;
    out.points.assign(path.begin(), path.end());
    // PlannerSimple2D leaves the start out; put it in so the path starts at the robot.
    if (out.points.empty() || (out.points.front() - mrpt::math::TPoint2D(start.x(), start.y())).norm() > 1e-6)
        out.points.insert(out.points.begin(), mrpt::math::TPoint2D(start.x(), start.y()));
    for (size_t i = 1; i < out.points.size(); ++i) out.length += (out.points[i] - out.points[i - 1]).norm();
    return out;
}

}  // namespace pndt::nav
