// PlannerRRT_SE2_TPS wrapper (path_planning.h).
#include <fmt/format.h>
#include <mrpt/nav/planners/PlannerRRT_SE2_TPS.h>
#include <pndt/nav/path_planning.h>

#include <cmath>
#include <filesystem>

namespace pndt::nav
{
PlannedPath planPathTPS(const mrpt::maps::CSimplePointsMap& obstacles, const mrpt::maps::COccupancyGridMap2D& grid,
                        const mrpt::math::TPose2D& start, const mrpt::math::TPose2D& goal,
                        const mrpt::config::CConfigFileBase& ptg_config, const TpsPlannerOptions& o)
{
    PlannedPath out;
    mrpt::nav::PlannerRRT_SE2_TPS planner;
    planner.getProfiler().enable(false);  // no timing report at exit
    planner.loadConfig(ptg_config, o.ptg_section);
    // The robot: an octagon around its circle (the differential-drive PTGs need a polygon).
    planner.params.robot_shape.clear();
    for (int k = 0; k < 8; ++k)
    {
        const double a = (k + 0.5) * M_PI / 4, r = o.robot_radius / std::cos(M_PI / 8);
        planner.params.robot_shape.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    planner.params.robot_shape_circular_radius = o.robot_radius;
    planner.params.ptg_verbose = false;
    planner.params.ptg_cache_files_directory =
        o.ptg_cache_dir.empty() ? (std::filesystem::temp_directory_path() / "pndt-nav-ptg-cache").string()
                                : o.ptg_cache_dir;
    std::filesystem::create_directories(planner.params.ptg_cache_files_directory);
    planner.params.maxLength = 2.0;
    planner.params.minDistanceBetweenNewNodes = 0.10;
    planner.params.minAngBetweenNewNodes = 10 * M_PI / 180;
    planner.params.goalBias = 0.1;
    planner.end_criteria.acceptedDistToTarget = o.goal_distance;
    planner.end_criteria.acceptedAngToTarget = o.goal_angle;
    planner.end_criteria.maxComputationTime = o.time_limit;
    planner.end_criteria.minComputationTime = 0;
    planner.initialize();

    mrpt::nav::PlannerRRT_SE2_TPS::TPlannerInput in;
    in.start_pose = start;
    in.goal_pose = goal;
    in.obstacles_points = obstacles;
    in.world_bbox_min = mrpt::math::TPose2D(grid.getXMin(), grid.getYMin(), -M_PI);
    in.world_bbox_max = mrpt::math::TPose2D(grid.getXMax(), grid.getYMax(), M_PI);
    mrpt::nav::PlannerRRT_SE2_TPS::TPlannerResult res;
    planner.solve(in, res);
    out.seconds = res.computation_time;
    if (!res.success || res.best_goal_node_id == mrpt::graphs::INVALID_NODEID)
    {
        out.reason = fmt::format("PlannerRRT_SE2_TPS found no path to ({:.2f}, {:.2f}, {:.0f} deg) in {:.1f} s "
                                 "(best {:.2f} m short)",
                                 goal.x, goal.y, goal.phi * 180 / M_PI, o.time_limit,
                                 res.goal_distance < 1e300 ? res.goal_distance : -1.0);
        return out;
    }
    mrpt::nav::TMoveTreeSE2_TP::path_t nodes;
    res.move_tree.backtrackPath(res.best_goal_node_id, nodes);
    for (const auto& n : nodes) out.points.emplace_back(n.state.x, n.state.y);
    for (size_t i = 1; i < out.points.size(); ++i) out.length += (out.points[i] - out.points[i - 1]).norm();
    out.found = true;
    return out;
}

}  // namespace pndt::nav
