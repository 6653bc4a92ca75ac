// Where a round robot fits in a navigation grid: clearance of every cell and the
// cells it can reach from a start.
#pragma once

#include <Eigen/Core>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <optional>
#include <vector>

namespace pndt::nav
{
/// Per cell (row-major, y rows), the distance in metres from the cell centre to
/// the nearest cell that is not free (occupied or unknown), minus half a cell:
/// how large a disc centred there can be. Non-free cells get 0.
class ClearanceMap
{
   public:
    explicit ClearanceMap(const mrpt::maps::COccupancyGridMap2D& grid);
    double at(int cx, int cy) const;
    double atPoint(double x, double y) const { return at(grid_->x2idx(x), grid_->y2idx(y)); }
    int cols() const { return nx_; }
    int rows() const { return ny_; }

   private:
    const mrpt::maps::COccupancyGridMap2D* grid_;
    int nx_ = 0, ny_ = 0;
    std::vector<float> clearance_;
};

/// Cells a disc of `robot_radius` can reach (8-connected moves between cells of
/// clearance >= robot_radius) from the start point; if no start is given (or it
/// is blocked), from the largest such region. Row-major, 1 = reachable.
struct Reachability
{
    std::vector<uint8_t> reachable;
    int nx = 0, ny = 0;
    bool from_start = false;  ///< false: the start was missing or blocked
    bool at(int cx, int cy) const
    {
        return cx >= 0 && cy >= 0 && cx < nx && cy < ny && reachable[size_t(cy) * nx + cx];
    }
};
Reachability reachableCells(const mrpt::maps::COccupancyGridMap2D& grid, const ClearanceMap& clearance,
                            double robot_radius, std::optional<Eigen::Vector2d> start);

}  // namespace pndt::nav
