// Height-band projection of the 3D map into a COccupancyGridMap2D (navigation_grid.h).
#include <fmt/format.h>
#include <pndt/nav/navigation_grid.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pndt::nav
{
CellState cellState(const mrpt::maps::COccupancyGridMap2D& grid, int cx, int cy)
{
    if (cx < 0 || cy < 0 || cx >= int(grid.getSizeX()) || cy >= int(grid.getSizeY())) return CellState::Unknown;
    const float p = grid.getCell(cx, cy);  // probability of free
    return p > 0.6f ? CellState::Free : p < 0.4f ? CellState::Occupied : CellState::Unknown;
}

CellState stateAt(const mrpt::maps::COccupancyGridMap2D& grid, double x, double y)
{
    return cellState(grid, grid.x2idx(x), grid.y2idx(y));
}

const char* toString(CellState s)
{
    return s == CellState::Free ? "free" : s == CellState::Occupied ? "occupied" : "unknown";
}

namespace
{
std::vector<bool> classMask(const ClassSet& classes, const std::vector<std::string>& names)
{
    std::vector<bool> mask(classes.size(), false);
    for (const std::string& n : names)
    {
        const int id = classes.find(n);
        if (id < 0 && (n == "floor" || n == "floor mat")) continue;  // defaults a class table may lack
        if (id < 0) throw InputError(fmt::format("unknown floor class '{}'", n));
        mask[size_t(id)] = true;
    }
    return mask;
}

/// Per-cell evidence, filled voxel by voxel.
struct CellEvidence
{
    std::vector<uint8_t> occupied, free_space, floor;
};
}  // namespace

NavigationGrid buildNavigationGrid(const PanopticMap& map, const GridOptions& o)
{
    const VoxelStore& store = map.voxels();
    if (store.empty()) throw InputError("the map is empty: no grid to build");
    const double vs = map.options().voxel_size;
    // 0 means the voxel size; a negative or NaN resolution is a mistake, not a default.
    if (!(o.resolution >= 0)) throw InputError(fmt::format("grid resolution {} m: give 0 (the voxel size) or 0.005-5 m", o.resolution));
    const double res = o.resolution > 0 ? o.resolution : vs;
    if (!(res >= 0.005 && res <= 5)) throw InputError(fmt::format("grid resolution {} m is out of range (0.005-5 m)", res));
    if (!(o.margin >= 0 && o.margin <= 100))
        throw InputError(fmt::format("grid margin {} m is out of range (0-100 m)", o.margin));
    if (!(o.inflation_radius >= 0 && o.inflation_radius <= 10))
        throw InputError(fmt::format("grid inflation radius {} m is out of range (0-10 m)", o.inflation_radius));
    if (!(o.floor_tolerance >= 0 && std::isfinite(o.floor_tolerance)))
        throw InputError(fmt::format("grid floor tolerance {} m must be a finite number >= 0", o.floor_tolerance));
    const ObstacleSelection sel = resolveObstacleOptions(map, o.obstacles);
    const std::vector<bool> floor_class = classMask(map.options().classes, o.floor_classes);
    NavigationGrid out;
    out.floor_z = o.obstacles.reference == HeightReference::Floor ? sel.floor_z : floorHeight(map);

    // Extent of everything the map knows (free or occupied).
    Eigen::Vector2d lo(std::numeric_limits<double>::max(), std::numeric_limits<double>::max()), hi = -lo;
    for (uint32_t i = 0; i < store.size(); ++i)
    {
        const Eigen::Vector3d c = map.grid().minCorner(store.key(i));
        lo = lo.cwiseMin(c.head<2>());
        hi = hi.cwiseMax(c.head<2>() + Eigen::Vector2d(vs, vs));
    }
    auto& g = out.grid;
    g.setSize(float(lo.x() - o.margin), float(hi.x() + o.margin), float(lo.y() - o.margin), float(hi.y() + o.margin),
              float(res), kUnknownCell);
    const int nx = int(g.getSizeX()), ny = int(g.getSizeY());
    CellEvidence ev;
    ev.occupied.assign(size_t(nx) * ny, 0);
    ev.free_space = ev.floor = ev.occupied;
    auto cellOf = [&](double x, double y) -> long {
        const int cx = g.x2idx(x), cy = g.y2idx(y);
        return cx < 0 || cy < 0 || cx >= nx || cy >= ny ? -1 : long(cy) * nx + cx;
    };
    // Marks the cells whose centres lie in [x0,x1]x[y0,y1], or the cell of
    // (x,y) when the box is smaller than a cell.
    auto markBox = [&](std::vector<uint8_t>& layer, double x, double y, double hx, double hy) {
        const int cx0 = g.x2idx(x - hx), cx1 = g.x2idx(x + hx), cy0 = g.y2idx(y - hy), cy1 = g.y2idx(y + hy);
        bool any = false;
        for (int cy = std::max(cy0, 0); cy <= std::min(cy1, ny - 1); ++cy)
            for (int cx = std::max(cx0, 0); cx <= std::min(cx1, nx - 1); ++cx)
                if (std::abs(g.idx2x(cx) - x) <= hx && std::abs(g.idx2y(cy) - y) <= hy)
                {
                    layer[size_t(cy) * nx + cx] = 1;
                    any = true;
                }
        if (!any)
            if (const long c = cellOf(x, y); c >= 0) layer[size_t(c)] = 1;
    };

    // Obstacles: at their NDT means (thin legs stay thin), spread over at most
    // their voxel when cells are finer than voxels.
    forEachObstacleVoxel(map, sel, 0.0, [&](uint32_t i, const Eigen::Vector3d& p) {
        double hx = 0, hy = 0;
        if (res < vs && map.hasGaussian(store[i]))
        {
            const Eigen::Matrix3d cov = map.gaussianOf(store[i]).cov;
            hx = std::min(2 * std::sqrt(cov(0, 0)), 0.5 * vs);
            hy = std::min(2 * std::sqrt(cov(1, 1)), 0.5 * vs);
        }
        markBox(ev.occupied, p.x(), p.y(), hx, hy);
    });
    // Free space in the band, and observed floor.
    for (uint32_t i = 0; i < store.size(); ++i)
    {
        const Voxel& v = store[i];
        if (map.isOccupied(v))
        {
            const Eigen::Vector3d p = map.pointOf(i);
            if (std::abs(p.z() - out.floor_z) > o.floor_tolerance) continue;
            const uint16_t c = map.panopticLabel(i).semantic;
            // Geometry-only voxels (void) at floor height count as floor too.
            if (c == 0 || (c < floor_class.size() && floor_class[c])) markBox(ev.floor, p.x(), p.y(), 0, 0);
            continue;
        }
        const Eigen::Vector3d lo_corner = map.grid().minCorner(store.key(i));
        if (lo_corner.z() + vs < sel.z_min || lo_corner.z() > sel.z_max) continue;
        markBox(ev.free_space, lo_corner.x() + 0.5 * vs, lo_corner.y() + 0.5 * vs, 0.5 * vs, 0.5 * vs);
    }
    for (int cy = 0; cy < ny; ++cy)
        for (int cx = 0; cx < nx; ++cx)
        {
            const size_t c = size_t(cy) * nx + cx;
            if (ev.occupied[c])
                g.setCell(cx, cy, kOccupiedCell);
            else if (ev.free_space[c] || ev.floor[c])
                g.setCell(cx, cy, kFreeCell);
        }
    if (o.inflation_radius > 0) inflateObstacles(g, o.inflation_radius);
    for (int cy = 0; cy < ny; ++cy)
        for (int cx = 0; cx < nx; ++cx)
        {
            const CellState s = cellState(g, cx, cy);
            ++(s == CellState::Free ? out.free_cells : s == CellState::Occupied ? out.occupied_cells : out.unknown_cells);
        }
    return out;
}

void inflateObstacles(mrpt::maps::COccupancyGridMap2D& g, double radius)
{
    const int nx = int(g.getSizeX()), ny = int(g.getSizeY());
    const int r = int(std::ceil(radius / g.getResolution()));
    const double r2 = std::pow(radius / g.getResolution(), 2);
    std::vector<std::pair<int, int>> seeds;
    for (int cy = 0; cy < ny; ++cy)
        for (int cx = 0; cx < nx; ++cx)
            if (cellState(g, cx, cy) == CellState::Occupied) seeds.emplace_back(cx, cy);
    for (const auto& [sx, sy] : seeds)
        for (int dy = -r; dy <= r; ++dy)
            for (int dx = -r; dx <= r; ++dx)
                if (dx * dx + dy * dy <= r2 && cellState(g, sx + dx, sy + dy) == CellState::Free)
                    g.setCell(sx + dx, sy + dy, kOccupiedCell);
}

}  // namespace pndt::nav
