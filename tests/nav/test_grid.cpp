// The 2D grid (pndt_nav) on the two-table room: cells free / occupied / unknown
// where the room says, the height band, inflation, agreement with the ground
// truth floor plan. On the map as built and as loaded.
#include <gtest/gtest.h>

#include <limits>
#include <pndt/nav/map_objects.h>
#include <pndt/nav/navigation_grid.h>

#include "nav_test_scene.h"

using namespace pndt;
using namespace pndt::nav;

namespace
{
class Grid : public ::testing::TestWithParam<std::string>
{
   protected:
    const PanopticMap& map() const { return navtest::mapNamed(GetParam()).core(); }
};

/// Ground truth: does a primitive standing in the band cover part of the cell?
bool truthOccupied(const sim::Scene& s, double cx, double cy, double res, double z_lo, double z_hi)
{
    for (const sim::Primitive& p : s.primitives)
    {
        const double ph = p.kind == sim::Primitive::Kind::Box ? p.half_extent.z() : p.half_height;
        if (p.center.z() + ph < z_lo || p.center.z() - ph > z_hi) continue;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
            {
                const double x = cx + res * ((i + 0.5) / 4 - 0.5), y = cy + res * ((j + 0.5) / 4 - 0.5);
                const double dx = x - p.center.x(), dy = y - p.center.y();
                if (p.kind == sim::Primitive::Kind::Cylinder)
                {
                    if (dx * dx + dy * dy <= p.radius * p.radius) return true;
                    continue;
                }
                const double c = std::cos(p.yaw), sn = std::sin(p.yaw);
                const double lx = c * dx + sn * dy, ly = -sn * dx + c * dy;
                if (std::abs(lx) <= p.half_extent.x() && std::abs(ly) <= p.half_extent.y()) return true;
            }
    }
    return false;
}
}  // namespace

TEST_P(Grid, CellsAreFreeOccupiedOrUnknownWhereTheRoomSays)
{
    const NavigationGrid g = buildNavigationGrid(map());
    EXPECT_NEAR(g.grid.getResolution(), 0.1, 1e-6);  // the voxel size
    EXPECT_NEAR(g.floor_z, 0, 0.03);
    EXPECT_EQ(g.free_cells + g.occupied_cells + g.unknown_cells, size_t(g.grid.getSizeX()) * g.grid.getSizeY());
    // Table tops are in the default band (up to 1.8 m): occupied.
    EXPECT_EQ(stateAt(g.grid, navtest::kTableA.x(), navtest::kTableA.y()), CellState::Occupied);
    EXPECT_EQ(stateAt(g.grid, navtest::kTableB.x(), navtest::kTableB.y()), CellState::Occupied);
    // Chair A5's seat.
    EXPECT_EQ(stateAt(g.grid, navtest::kTableA.x() + 1.15, 0.0), CellState::Occupied);
    // Open floor between the tables and the walls.
    for (const Eigen::Vector2d& p : {Eigen::Vector2d(0.1, -2.2), Eigen::Vector2d(0.1, 2.2), Eigen::Vector2d(0.05, 0.05)})
        EXPECT_EQ(stateAt(g.grid, p.x(), p.y()), CellState::Free) << p.transpose();
    // The wall at x = +4 m, beyond it nothing was seen.
    bool wall = false;
    for (double x = 3.85; x <= 4.1; x += 0.05) wall |= stateAt(g.grid, x, 1.0) == CellState::Occupied;
    EXPECT_TRUE(wall);
    EXPECT_EQ(stateAt(g.grid, 4.4, 1.0), CellState::Unknown);
}

TEST_P(Grid, ALaserHighBandSeesTableLegsButNotTheTop)
{
    GridOptions o;
    o.obstacles.max_height = 0.5;
    const NavigationGrid g = buildNavigationGrid(map(), o);
    EXPECT_NE(stateAt(g.grid, navtest::kTableA.x(), navtest::kTableA.y()), CellState::Occupied);
    // Table A's leg at (+0.72, +0.37) from its centre (6 cm legs, 5 cm inset).
    EXPECT_EQ(stateAt(g.grid, navtest::kTableA.x() + 0.72, navtest::kTableA.y() + 0.37), CellState::Occupied);
}

TEST_P(Grid, InflationGrowsObstaclesByTheRadius)
{
    GridOptions o;
    const NavigationGrid plain = buildNavigationGrid(map(), o);
    o.inflation_radius = 0.3;
    const NavigationGrid grown = buildNavigationGrid(map(), o);
    // 0.25 m in front of the wall at y = +3: free, then inside the inflated band.
    EXPECT_EQ(stateAt(plain.grid, 0.05, 2.75), CellState::Free);
    EXPECT_EQ(stateAt(grown.grid, 0.05, 2.75), CellState::Occupied);
    EXPECT_EQ(stateAt(grown.grid, 0.05, 2.2), CellState::Free);  // 0.8 m away: untouched
    EXPECT_GT(grown.occupied_cells, plain.occupied_cells);
    EXPECT_EQ(grown.unknown_cells, plain.unknown_cells);
}

TEST_P(Grid, OccupiedCellsAgreeWithTheFloorPlan)
{
    // Inside the room (off the walls), cells the map saw: IoU of "occupied".
    const NavigationGrid g = buildNavigationGrid(map());
    size_t both = 0, either = 0, unknown_inside = 0, inside = 0;
    for (int cy = 0; cy < int(g.grid.getSizeY()); ++cy)
        for (int cx = 0; cx < int(g.grid.getSizeX()); ++cx)
        {
            const double x = g.grid.idx2x(cx), y = g.grid.idx2y(cy);
            if (std::abs(x) > navtest::kRoomHalfX - 0.15 || std::abs(y) > navtest::kRoomHalfY - 0.15) continue;
            ++inside;
            const CellState s = cellState(g.grid, cx, cy);
            if (s == CellState::Unknown) ++unknown_inside;
            const bool map_occ = s == CellState::Occupied;
            const bool gt_occ = truthOccupied(navtest::scene(), x, y, 0.1, 0.05, 1.8);
            both += map_occ && gt_occ;
            either += map_occ || gt_occ;
        }
    const double iou = double(both) / double(either);
    std::cout << "  occupied IoU vs floor plan " << iou << " (" << both << "/" << either << "), unknown inside "
              << unknown_inside << "/" << inside << "\n";
    EXPECT_GE(iou, 0.9);  // measured 0.91 (issue #20: >= 0.9 at 10 cm)
    EXPECT_LT(double(unknown_inside) / inside, 0.1);
}

TEST(GridErrors, EmptyMapAndBadOptionsAreClearErrors)
{
    try
    {
        buildNavigationGrid(PanopticMap());
        FAIL();
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
    }
    GridOptions o;
    o.floor_classes = {"lava"};
    EXPECT_THROW(buildNavigationGrid(navtest::builtMap().core(), o), InputError);
    o = {};
    o.obstacles.min_height = 2;
    o.obstacles.max_height = 1;
    EXPECT_THROW(buildNavigationGrid(navtest::builtMap().core(), o), InputError);
    // A negative or NaN resolution was read as "the voxel size", a NaN margin gave a 0 x 0 grid,
    // a huge one bad_alloc, a negative one MRPT's assertion: each a clear error now.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const double bad : {-0.1, nan})
    {
        o = {};
        o.resolution = bad;
        EXPECT_THROW(buildNavigationGrid(navtest::builtMap().core(), o), InputError) << bad;
    }
    for (const double bad : {-5.0, nan, 1e6})
    {
        o = {};
        o.margin = bad;
        EXPECT_THROW(buildNavigationGrid(navtest::builtMap().core(), o), InputError) << bad;
    }
    o = {};
    o.inflation_radius = nan;
    EXPECT_THROW(buildNavigationGrid(navtest::builtMap().core(), o), InputError);
}

INSTANTIATE_TEST_SUITE_P(BuiltLoadedNoisy, Grid, ::testing::Values("built", "loaded", "noisy"));

TEST(GridGeometryOnly, AMapWithoutLabelsStillGivesFloorObstaclesAndGrid)
{
    // No segmentation (pndt-map's geometry-only mode): the floor comes from the
    // fullest low voxel layer, obstacles from the band, the grid as before.
    PanopticNDTMap m;
    for (const Pose& T : navtest::cameraPoses())
    {
        PanopticFrame f = navtest::renderFrame(T);
        f.semantic = {};
        f.semantic_score = {};
        f.instance = {};
        f.panoptic_score = {};
        m.integrate(f, T);
    }
    EXPECT_NEAR(floorHeight(m.core()), 0.0, 0.05);
    const NavigationGrid g = buildNavigationGrid(m.core());
    EXPECT_EQ(stateAt(g.grid, navtest::kTableA.x(), navtest::kTableA.y()), CellState::Occupied);
    EXPECT_EQ(stateAt(g.grid, 0.1, -2.2), CellState::Free);
    EXPECT_EQ(stateAt(g.grid, 0.05, 0.05), CellState::Free);
    EXPECT_TRUE(mapObjects(m.core()).empty());
}

TEST(GridClassTable, AClassTableWithoutFloorOrCeilingNeedsNoOptions)
{
    // The default exclusions name NYUv2-40 classes; another class table may lack them.
    MapOptions o;
    o.classes = ClassSet({{"void", false}, {"thing", true}});
    PanopticNDTMap m(o);
    const auto poses = navtest::cameraPoses();
    for (size_t i = 0; i < poses.size(); i += 3)
    {
        PanopticFrame f = navtest::renderFrame(poses[i]);
        f.semantic = {};
        f.semantic_score = {};
        f.instance = {};
        f.panoptic_score = {};
        m.integrate(f, poses[i]);
    }
    EXPECT_NO_THROW(buildNavigationGrid(m.core()));
    mrpt::maps::CSimplePointsMap pts;
    EXPECT_NO_THROW(obstaclePoints(m.core(), {}, pts));
    EXPECT_GT(pts.size(), 0u);
    ObstacleOptions bad;
    bad.excluded_classes = {"chair"};  // asked for by name: an error
    EXPECT_THROW(obstaclePoints(m.core(), bad, pts), InputError);
}
