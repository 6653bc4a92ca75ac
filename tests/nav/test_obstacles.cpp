// Obstacle points (plugin: obstaclePoints, getAsSimplePointsMap) on the two-table
// room, on the map as built and as loaded from its .pndt.gz.
#include <gtest/gtest.h>

#include <limits>
#include <pndt/mrpt/obstacle_points.h>

#include "nav_test_scene.h"

using namespace pndt;

namespace
{
class Obstacles : public ::testing::TestWithParam<std::string>
{
   protected:
    const PanopticNDTMap& map() const { return navtest::mapNamed(GetParam()); }
};

size_t pointsIn(const mrpt::maps::CSimplePointsMap& pts, const Eigen::Vector2d& c, const Eigen::Vector2d& half,
                double z_lo, double z_hi)
{
    size_t n = 0;
    for (size_t i = 0; i < pts.size(); ++i)
    {
        float x, y, z;
        pts.getPoint(i, x, y, z);
        if (std::abs(x - c.x()) <= half.x() && std::abs(y - c.y()) <= half.y() && z >= z_lo && z <= z_hi) ++n;
    }
    return n;
}
}  // namespace

TEST_P(Obstacles, FloorIsFoundAtZeroFromItsLabels)
{
    EXPECT_NEAR(floorHeight(map().core()), 0.0, 0.03);
}

TEST_P(Obstacles, BandKeepsOnlyHeightsInsideItAndNoFloor)
{
    ObstacleOptions o;
    o.min_height = 0.05;
    o.max_height = 0.5;  // a low band: chair legs and seats, table legs, no table top
    mrpt::maps::CSimplePointsMap pts;
    obstaclePoints(map().core(), o, pts);
    ASSERT_GT(pts.size(), 100u);
    for (size_t i = 0; i < pts.size(); ++i)
    {
        float x, y, z;
        pts.getPoint(i, x, y, z);
        ASSERT_GE(z, 0.05f);
        ASSERT_LE(z, 0.5f);
    }
    // The table top (z 0.70-0.75) is above the band: nothing over table A's middle.
    EXPECT_EQ(pointsIn(pts, navtest::kTableA, {0.5, 0.25}, 0.0, 3.0), 0u);
    // A chair seat (top at 0.45) is inside it: chair A5 at table A's +x end.
    EXPECT_GT(pointsIn(pts, navtest::kTableA + Eigen::Vector2d(1.15, 0), {0.25, 0.25}, 0.3, 0.5), 3u);

    o.max_height = 1.0;  // now the table top is in
    obstaclePoints(map().core(), o, pts);
    EXPECT_GT(pointsIn(pts, navtest::kTableA, {0.5, 0.25}, 0.65, 0.8), 20u);
}

TEST_P(Obstacles, ClassFilterLeavesOutChairs)
{
    ObstacleOptions o;
    mrpt::maps::CSimplePointsMap all, no_chairs;
    obstaclePoints(map().core(), o, all);
    o.excluded_classes.push_back("chair");
    obstaclePoints(map().core(), o, no_chairs);
    const Eigen::Vector2d a5 = navtest::kTableA + Eigen::Vector2d(1.15, 0);
    EXPECT_GT(pointsIn(all, a5, {0.2, 0.2}, 0.1, 1.0), 5u);
    EXPECT_EQ(pointsIn(no_chairs, a5, {0.2, 0.2}, 0.1, 1.0), 0u);
    EXPECT_LT(no_chairs.size(), all.size());
}

TEST_P(Obstacles, CeilingAndWallsTopAreOutsideTheDefaultBand)
{
    mrpt::maps::CSimplePointsMap pts;
    obstaclePoints(map().core(), {}, pts);  // 0.05 .. 1.8 m above the floor, floor and ceiling out
    EXPECT_EQ(pointsIn(pts, {0, 0}, {5, 5}, 1.81, 10), 0u);
    // A wall is an obstacle: points along x = +4 at robot height.
    EXPECT_GT(pointsIn(pts, {3.95, 0}, {0.1, 2.0}, 0.2, 1.5), 20u);
}

TEST_P(Obstacles, UnknownClassIsAnErrorNamingIt)
{
    ObstacleOptions o;
    o.excluded_classes = {"floor", "sofa-bed"};
    mrpt::maps::CSimplePointsMap pts;
    try
    {
        obstaclePoints(map().core(), o, pts);
        FAIL() << "no error";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("'sofa-bed'"), std::string::npos) << e.what();
    }
}

TEST_P(Obstacles, AroundTheRobotInItsOwnFrame)
{
    // Robot at the room centre facing +y: the wall at y = +3 lies ~3 m ahead (local +x).
    const mrpt::poses::CPose3D robot(0, 0, 0, M_PI / 2, 0, 0);
    mrpt::maps::CSimplePointsMap local;
    obstaclePointsAround(map().core(), {}, robot, 3.2, local);
    ASSERT_GT(local.size(), 0u);
    size_t ahead = 0;
    for (size_t i = 0; i < local.size(); ++i)
    {
        float x, y, z;
        local.getPoint(i, x, y, z);
        ASSERT_LE(std::hypot(x, y), 3.2 + 1e-4);
        if (std::abs(x - 3.0f) < 0.08f && std::abs(y) < 0.5f) ++ahead;
    }
    EXPECT_GT(ahead, 3u);
    // A NaN pose or radius returned every point (with NaN coordinates), a negative
    // radius acted as its square: errors now.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(obstaclePointsAround(map().core(), {}, mrpt::poses::CPose3D(nan, 0, 0, 0, 0, 0), 3.2, local),
                 std::invalid_argument);
    EXPECT_THROW(obstaclePointsAround(map().core(), {}, robot, nan, local), std::invalid_argument);
    EXPECT_THROW(obstaclePointsAround(map().core(), {}, robot, -1, local), std::invalid_argument);
}

TEST_P(Obstacles, GetAsSimplePointsMapIsTheCachedObstacleSet)
{
    PanopticNDTMap m = map();  // a copy: its own cache
    const mrpt::maps::CMetricMap& as_metric = m;
    const mrpt::maps::CSimplePointsMap* p1 = as_metric.getAsSimplePointsMap();
    ASSERT_NE(p1, nullptr);
    mrpt::maps::CSimplePointsMap direct;
    obstaclePoints(m.core(), m.navigationOptions.obstacles, direct);
    EXPECT_EQ(p1->size(), direct.size());
    EXPECT_EQ(as_metric.getAsSimplePointsMap(), p1);  // same object, not rebuilt
    // Options change: recomputed.
    m.navigationOptions.obstacles.max_height = 0.5;
    EXPECT_LT(as_metric.getAsSimplePointsMap()->size(), direct.size());
}

TEST(ObstacleCache, IntegratingMoreFramesRefreshesThePoints)
{
    const auto poses = navtest::cameraPoses();
    PanopticNDTMap m;
    for (size_t i = 0; i < 10; ++i) m.integrate(navtest::renderFrame(poses[i]), poses[i]);
    const size_t before = m.getAsSimplePointsMap()->size();
    for (size_t i = 10; i < poses.size(); ++i) m.integrate(navtest::renderFrame(poses[i]), poses[i]);
    mrpt::maps::CSimplePointsMap direct;
    obstaclePoints(m.core(), m.navigationOptions.obstacles, direct);
    EXPECT_NE(m.getAsSimplePointsMap()->size(), before);
    EXPECT_EQ(m.getAsSimplePointsMap()->size(), direct.size());
}

INSTANTIATE_TEST_SUITE_P(BuiltAndLoaded, Obstacles, ::testing::Values("built", "loaded"));
