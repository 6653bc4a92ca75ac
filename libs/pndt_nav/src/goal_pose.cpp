// Goal poses next to objects (goal_pose.h).
#include <fmt/format.h>
#include <pndt/nav/goal_pose.h>
#include <pndt/nav/navigation_grid.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pndt::nav
{
std::vector<int> defaultKeepClearClasses(const ClassSet& classes)
{
    std::vector<int> out;
    for (const char* n : {"chair", "door"})
        if (const int id = classes.find(n); id >= 0) out.push_back(id);
    return out;
}

namespace
{
/// Points every `step` along the edge of the rectangle.
std::vector<Eigen::Vector2d> perimeterPoints(const Footprint& f, double step)
{
    std::vector<Eigen::Vector2d> out;
    const auto c = f.corners();
    for (int i = 0; i < 4; ++i)
    {
        const Eigen::Vector2d a = c[i], b = c[(i + 1) % 4];
        const int n = std::max(1, int(std::ceil((b - a).norm() / step)));
        for (int k = 0; k < n; ++k) out.push_back(a + (b - a) * (double(k) / n));
    }
    return out;
}
}  // namespace

GoalPose goalNextTo(const MapObject& target, const std::vector<MapObject>& objects,
                    const mrpt::maps::COccupancyGridMap2D& grid, const GoalOptions& o)
{
    GoalPose g;
    g.object_id = target.id;
    if (!(o.robot_radius > 0 && std::isfinite(o.robot_radius))) throw InputError("goal: robot radius must be positive");
    if (!(o.standoff >= 0 && o.max_standoff >= o.standoff && o.max_standoff <= 50))
        throw InputError(fmt::format("goal: standoff {} m and max standoff {} m must satisfy 0 <= standoff <= max <= 50",
                                     o.standoff, o.max_standoff));
    if (o.start && !o.start->allFinite())
        throw InputError(fmt::format("goal: the start ({}, {}) is not a finite point", o.start->x(), o.start->y()));
    const ClearanceMap clearance(grid);
    const Reachability reach = reachableCells(grid, clearance, o.robot_radius, o.start);
    const double res = grid.getResolution();
    std::vector<const MapObject*> keep_clear;
    for (const MapObject& m : objects)
        if (m.id != target.id &&
            std::find(o.keep_clear_classes.begin(), o.keep_clear_classes.end(), m.class_id) != o.keep_clear_classes.end())
            keep_clear.push_back(&m);

    for (double d = o.robot_radius + o.standoff; d <= o.robot_radius + o.max_standoff + 1e-9; d += res)
    {
        const Footprint ring = target.footprint.grown(d);
        double best_score = std::numeric_limits<double>::infinity();
        for (const Eigen::Vector2d& p : perimeterPoints(ring, res))
        {
            ++g.candidates;
            const int cx = grid.x2idx(p.x()), cy = grid.y2idx(p.y());
            if (cellState(grid, cx, cy) != CellState::Free || clearance.at(cx, cy) < o.robot_radius)
            {
                ++g.rejected_blocked;
                continue;
            }
            if (!reach.at(cx, cy))
            {
                ++g.rejected_unreachable;
                continue;
            }
            const bool blocks = std::any_of(keep_clear.begin(), keep_clear.end(), [&](const MapObject* m) {
                return m->footprint.distanceTo(p) < o.robot_radius + o.keep_clear_distance;
            });
            if (blocks)
            {
                ++g.rejected_keep_clear;
                continue;
            }
            // Nearest the start; without one, the middle of a long side (most room to wait).
            const double score = o.start ? (p - *o.start).norm()
                                         : std::abs(target.footprint.toLocal(p).x()) - 10 * std::abs(target.footprint.toLocal(p).y());
            if (score < best_score)
            {
                best_score = score;
                g.found = true;
                g.x = p.x();
                g.y = p.y();
                g.clearance = clearance.at(cx, cy);
            }
        }
        if (g.found) break;
    }
    if (!g.found)
    {
        g.reason = fmt::format(
            "no free, reachable pose with clearance >= {:.2f} m within {:.2f} m of {} {} ({} candidates: {} blocked or "
            "too tight, {} unreachable{}, {} in front of a chair or door)",
            o.robot_radius, o.max_standoff, target.class_name, target.id, g.candidates, g.rejected_blocked,
            g.rejected_unreachable, reach.from_start ? " from the start" : "", g.rejected_keep_clear);
        return g;
    }
    const Eigen::Vector2d to = target.footprint.center - Eigen::Vector2d(g.x, g.y);
    g.yaw = std::atan2(to.y(), to.x());
    g.distance_to_object = target.footprint.distanceTo({g.x, g.y});
    return g;
}

}  // namespace pndt::nav
