// The map projected to a 2D COccupancyGridMap2D for MRPT's planners
// (PlannerSimple2D and friends): a cell is occupied when an obstacle voxel
// (obstacle_points.h: occupied, in the height band, class not left out) lies
// over it, free when free space or floor was observed over it, else unknown.
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <pndt/mrpt/obstacle_points.h>

#include <string>
#include <vector>

namespace pndt::nav
{
struct GridOptions
{
    /// Cell size in metres; 0 = the map's voxel size.
    double resolution = 0;
    /// Height band and classes of the obstacles (default: 5 cm to 1.8 m above the
    /// floor, floor and ceiling left out).
    ObstacleOptions obstacles;
    /// Occupied voxels of these classes within floor_tolerance of the floor make
    /// their cell traversable (observed floor). Unknown names are an error, except
    /// the defaults, which a non-NYUv2 class table may lack.
    std::vector<std::string> floor_classes{"floor", "floor mat"};
    double floor_tolerance = 0.15;
    /// Occupied cells grown by this radius (metres; 0 = none). PlannerSimple2D
    /// grows obstacles by its own robotRadius, so leave 0 for it.
    double inflation_radius = 0;
    /// Unknown border kept around the map's extent (metres).
    double margin = 0.3;
};

/// Cell values written: the MRPT convention stores the probability of *free*.
constexpr float kFreeCell = 1.0f, kOccupiedCell = 0.0f, kUnknownCell = 0.5f;

enum class CellState
{
    Unknown,
    Free,
    Occupied
};
/// Out-of-grid cells are unknown.
CellState cellState(const mrpt::maps::COccupancyGridMap2D& grid, int cx, int cy);
CellState stateAt(const mrpt::maps::COccupancyGridMap2D& grid, double x, double y);
const char* toString(CellState s);

struct NavigationGrid
{
    mrpt::maps::COccupancyGridMap2D grid;
    double floor_z = 0;  ///< world z the band was measured from
    size_t free_cells = 0, occupied_cells = 0, unknown_cells = 0;
};

/// Throws InputError for an empty map, a bad resolution or an unknown class name.
NavigationGrid buildNavigationGrid(const PanopticMap& map, const GridOptions& options = {});

/// Occupied cells grown by `radius` metres: free cells within it become occupied.
void inflateObstacles(mrpt::maps::COccupancyGridMap2D& grid, double radius);

}  // namespace pndt::nav
