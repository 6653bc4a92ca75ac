// A picture of the navigation grid with the objects (labelled footprints), the
// chosen object, the goal pose and the path: what pndt-nav writes as PNG.
#pragma once

#include <pndt/nav/goal_pose.h>
#include <pndt/nav/navigation_grid.h>
#include <pndt/nav/path_planning.h>

#include <string>
#include <vector>

namespace pndt::nav
{
struct GridPicture
{
    const NavigationGrid* grid = nullptr;
    const std::vector<MapObject>* objects = nullptr;
    uint32_t highlight_id = 0;           ///< drawn thicker (0 = none)
    const GoalPose* goal = nullptr;
    const PlannedPath* path = nullptr;
    std::vector<Eigen::Vector2d> trajectory;  ///< e.g. a simulated robot's, drawn dotted
    int scale = 8;                        ///< pixels per cell
};

/// Writes a PNG (free white, occupied black, unknown grey; north = +y up). Throws
/// std::runtime_error naming the file if it cannot be written.
void writeGridPicture(const GridPicture& p, const std::string& png_path);

}  // namespace pndt::nav
