// A waiting pose for a round robot next to an object: free and reachable in the
// 2D grid, clearance >= robot radius, facing the object, and not in front of a
// chair or a door (it must not block them).
#pragma once

#include <pndt/nav/grid_geometry.h>
#include <pndt/nav/map_objects.h>

#include <optional>
#include <string>
#include <vector>

namespace pndt::nav
{
struct GoalOptions
{
    double robot_radius = 0.30;
    /// Gap wanted between the robot's disc and the object's footprint (m); the
    /// search moves outwards from here in grid-cell steps up to max_standoff.
    double standoff = 0.10;
    double max_standoff = 1.5;
    /// The robot's disc keeps this far from objects of these classes (other than
    /// the target): it must not block a chair or a door.
    std::vector<int> keep_clear_classes;
    double keep_clear_distance = 0.25;
    /// Where the robot is (reachability is from here); none = the largest free region.
    std::optional<Eigen::Vector2d> start;
};

struct GoalPose
{
    bool found = false;
    double x = 0, y = 0, yaw = 0;        ///< yaw faces the object's footprint centre
    double clearance = 0;                ///< of the goal cell (m)
    double distance_to_object = 0;       ///< from the goal to the footprint (m)
    uint32_t object_id = 0;
    size_t candidates = 0, rejected_blocked = 0, rejected_unreachable = 0, rejected_keep_clear = 0;
    std::string reason;  ///< why none was found
};

/// Candidates lie on rectangles around the footprint (grown by robot radius +
/// standoff, then by one cell more each round) every grid cell along the edge;
/// the first round with a valid candidate wins, and in it the candidate nearest
/// the start (or the footprint's long side when there is no start).
GoalPose goalNextTo(const MapObject& target, const std::vector<MapObject>& objects,
                    const mrpt::maps::COccupancyGridMap2D& grid, const GoalOptions& options);

/// Default keep-clear classes of a class table: chair and door (those it has).
std::vector<int> defaultKeepClearClasses(const ClassSet& classes);

}  // namespace pndt::nav
