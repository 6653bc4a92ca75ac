// Clearance (Euclidean distance transform) and reachability on a grid (grid_geometry.h).
#include <opencv2/imgproc.hpp>
#include <pndt/nav/grid_geometry.h>
#include <pndt/nav/navigation_grid.h>

#include <algorithm>
#include <deque>

namespace pndt::nav
{
ClearanceMap::ClearanceMap(const mrpt::maps::COccupancyGridMap2D& grid)
    : grid_(&grid), nx_(int(grid.getSizeX())), ny_(int(grid.getSizeY()))
{
    cv::Mat1b free_mask(ny_, nx_);
    for (int cy = 0; cy < ny_; ++cy)
        for (int cx = 0; cx < nx_; ++cx) free_mask(cy, cx) = cellState(grid, cx, cy) == CellState::Free ? 255 : 0;
    // The grid's border counts as not free: a robot cannot leave the known map.
    cv::Mat1b padded;
    cv::copyMakeBorder(free_mask, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, 0);
    cv::Mat1f dist;
    cv::distanceTransform(padded, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    const double res = grid.getResolution();
    clearance_.resize(size_t(nx_) * ny_);
    for (int cy = 0; cy < ny_; ++cy)
        for (int cx = 0; cx < nx_; ++cx)
        {
            const float d = dist(cy + 1, cx + 1);
            clearance_[size_t(cy) * nx_ + cx] = d > 0 ? float(std::max(0.0, (d - 0.5) * res)) : 0.f;
        }
}

double ClearanceMap::at(int cx, int cy) const
{
    if (cx < 0 || cy < 0 || cx >= nx_ || cy >= ny_) return 0;
    return clearance_[size_t(cy) * nx_ + cx];
}

namespace
{
/// Flood fill of the cells with enough clearance from `seed`; returns the count.
size_t flood(const ClearanceMap& c, double radius, int sx, int sy, int label, std::vector<int>& labels)
{
    const int nx = c.cols(), ny = c.rows();
    std::deque<std::pair<int, int>> q{{sx, sy}};
    labels[size_t(sy) * nx + sx] = label;
    size_t n = 0;
    while (!q.empty())
    {
        const auto [x, y] = q.front();
        q.pop_front();
        ++n;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
            {
                const int X = x + dx, Y = y + dy;
                if (X < 0 || Y < 0 || X >= nx || Y >= ny) continue;
                int& l = labels[size_t(Y) * nx + X];
                if (l != 0 || c.at(X, Y) < radius) continue;
                l = label;
                q.emplace_back(X, Y);
            }
    }
    return n;
}
}  // namespace

Reachability reachableCells(const mrpt::maps::COccupancyGridMap2D& grid, const ClearanceMap& clearance,
                            double robot_radius, std::optional<Eigen::Vector2d> start)
{
    Reachability r;
    r.nx = clearance.cols();
    r.ny = clearance.rows();
    std::vector<int> labels(size_t(r.nx) * r.ny, 0);
    int keep = -1;
    if (start)
    {
        const int sx = grid.x2idx(start->x()), sy = grid.y2idx(start->y());
        if (clearance.at(sx, sy) >= robot_radius)
        {
            flood(clearance, robot_radius, sx, sy, 1, labels);
            keep = 1;
            r.from_start = true;
        }
    }
    if (keep < 0)
    {
        size_t best = 0;
        int next = 1;
        for (int cy = 0; cy < r.ny; ++cy)
            for (int cx = 0; cx < r.nx; ++cx)
                if (labels[size_t(cy) * r.nx + cx] == 0 && clearance.at(cx, cy) >= robot_radius)
                {
                    const size_t n = flood(clearance, robot_radius, cx, cy, next, labels);
                    if (n > best)
                    {
                        best = n;
                        keep = next;
                    }
                    ++next;
                }
    }
    r.reachable.resize(labels.size());
    for (size_t i = 0; i < labels.size(); ++i) r.reachable[i] = labels[i] == keep && keep > 0;
    return r;
}

}  // namespace pndt::nav
