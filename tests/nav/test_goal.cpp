// A goal pose next to the table with the most chairs, and a path to it with
// MRPT's PlannerSimple2D, checked against the ground-truth furniture. On the map
// as built and as loaded.
#include <gtest/gtest.h>

#include <limits>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/random/RandomGenerators.h>
#include <pndt/nav/goal_pose.h>
#include <pndt/nav/navigation_grid.h>
#include <pndt/nav/object_query.h>
#include <pndt/nav/path_planning.h>

#include "nav_test_scene.h"

using namespace pndt;
using namespace pndt::nav;

namespace
{
const Eigen::Vector2d kStart(0.1, -2.2);
constexpr double kRadius = 0.3;

/// Distance from a floor point to the nearest ground-truth furniture footprint or wall.
double truthClearance(const Eigen::Vector2d& p)
{
    double d = std::min({navtest::kRoomHalfX - std::abs(p.x()), navtest::kRoomHalfY - std::abs(p.y())});
    for (const navtest::ObjectTruth& t : navtest::truth())
    {
        const Eigen::Vector2d q = (p - t.xy).cwiseAbs() - t.half;
        d = std::min(d, q.cwiseMax(0.0).norm());
    }
    return d;
}

class Goal : public ::testing::TestWithParam<std::string>
{
   protected:
    const PanopticMap& map() const { return navtest::mapNamed(GetParam()).core(); }
};
}  // namespace

TEST_P(Goal, NextToTheTableWithTheMostChairsFreeReachableAndFacingIt)
{
    const NavigationGrid g = buildNavigationGrid(map());
    const auto objs = mapObjects(map(), "", 5);
    const QueryResult q = runQuery(objs, map().options().classes, "table with most chairs");
    ASSERT_TRUE(q.best());
    const MapObject& table = *q.best();
    GoalOptions o;
    o.robot_radius = kRadius;
    o.start = kStart;
    o.keep_clear_classes = defaultKeepClearClasses(map().options().classes);
    const GoalPose goal = goalNextTo(table, objs, g.grid, o);
    ASSERT_TRUE(goal.found) << goal.reason;
    std::cout << "  goal (" << goal.x << ", " << goal.y << ", " << goal.yaw * 180 / M_PI << " deg), clearance "
              << goal.clearance << " m, " << goal.distance_to_object << " m from table " << table.id << "\n";
    const Eigen::Vector2d at(goal.x, goal.y);
    EXPECT_EQ(stateAt(g.grid, goal.x, goal.y), CellState::Free);
    EXPECT_GE(goal.clearance, kRadius);
    EXPECT_GE(truthClearance(at), kRadius) << "the robot's disc touches furniture or a wall";
    EXPECT_GE(goal.distance_to_object, kRadius + o.standoff - 0.1);
    EXPECT_LE(goal.distance_to_object, kRadius + o.max_standoff);
    // Facing the table.
    const Eigen::Vector2d to = table.footprint.center - at;
    EXPECT_NEAR(std::remainder(goal.yaw - std::atan2(to.y(), to.x()), 2 * M_PI), 0, 1e-9);
    // Not blocking any chair.
    for (const MapObject& m : objs)
    {
        if (m.class_name == "chair")
        {
            EXPECT_GE(m.footprint.distanceTo(at), kRadius + o.keep_clear_distance - 1e-9);
        }
    }

    // MRPT's planner gets there, never closer than the robot's radius (less a cell) to the furniture.
    const PlannedPath path = planPath(g.grid, kStart, at, kRadius);
    ASSERT_TRUE(path.found) << path.reason;
    std::cout << "  path: " << path.points.size() << " points, " << path.length << " m, planned in "
              << path.seconds * 1000 << " ms\n";
    EXPECT_LT((Eigen::Vector2d(path.points.back().x, path.points.back().y) - at).norm(), 0.15);
    EXPECT_GE(path.length, (at - kStart).norm() - 0.15);
    for (size_t i = 1; i < path.points.size(); ++i)
        for (int k = 0; k <= 10; ++k)
        {
            const auto a = path.points[i - 1], b = path.points[i];
            const Eigen::Vector2d p(a.x + (b.x - a.x) * k / 10, a.y + (b.y - a.y) * k / 10);
            ASSERT_GE(truthClearance(p), kRadius - 0.1) << "path point " << p.transpose();
        }
}

TEST_P(Goal, WithoutAStartTheMiddleOfALongSide)
{
    const NavigationGrid g = buildNavigationGrid(map());
    const auto objs = mapObjects(map(), "", 5);
    const MapObject& table_b = *runQuery(objs, map().options().classes, "table with 3 chairs").best();
    GoalOptions o;  // no keep-clear classes: the chairs are only obstacles
    const GoalPose goal = goalNextTo(table_b, objs, g.grid, o);
    ASSERT_TRUE(goal.found) << goal.reason;
    EXPECT_GE(truthClearance({goal.x, goal.y}), o.robot_radius);
}

TEST_P(Goal, NoRoomForAHugeRobotIsAClearAnswer)
{
    const NavigationGrid g = buildNavigationGrid(map());
    const auto objs = mapObjects(map(), "", 5);
    GoalOptions o;
    o.robot_radius = 2.5;  // wider than the room is free anywhere
    const GoalPose goal = goalNextTo(objs.front(), objs, g.grid, o);
    EXPECT_FALSE(goal.found);
    EXPECT_NE(goal.reason.find("no free, reachable pose"), std::string::npos) << goal.reason;
    GoalOptions no_radius;
    no_radius.robot_radius = 0;
    EXPECT_THROW(goalNextTo(objs.front(), objs, g.grid, no_radius), InputError);
    // A NaN start never scored better than infinity: "no pose found" blamed the map.
    GoalOptions nan_start;
    nan_start.start = Eigen::Vector2d(std::numeric_limits<double>::quiet_NaN(), 0);
    EXPECT_THROW(goalNextTo(objs.front(), objs, g.grid, nan_start), InputError);
    EXPECT_FALSE(planPath(g.grid, kStart, {0, 0}, -1).found);
    // Outside the map: refused before MRPT's planner, which indexes the grid there unchecked
    // (a SEGV under ASan).
    const PlannedPath none = planPath(g.grid, kStart, {6, 6}, 0.3);
    EXPECT_FALSE(none.found);
    EXPECT_NE(none.reason.find("the goal (6.00, 6.00) is outside the grid"), std::string::npos) << none.reason;
    const PlannedPath from_outside = planPath(g.grid, {-40, 0}, kStart, 0.3);
    EXPECT_FALSE(from_outside.found);
    EXPECT_NE(from_outside.reason.find("the start (-40.00, 0.00) is outside the grid"), std::string::npos)
        << from_outside.reason;
}

INSTANTIATE_TEST_SUITE_P(BuiltLoadedNoisy, Goal, ::testing::Values("built", "loaded", "noisy"));

TEST(GoalTps, TheTpSpacePlannerReachesTheGoalPoseWithItsHeading)
{
    // MRPT's TP-Space RRT with the map's obstacle points and the navigator's PTGs.
    mrpt::random::getRandomGenerator().randomize(3);
    const PanopticNDTMap& m = navtest::builtMap();
    const NavigationGrid g = buildNavigationGrid(m.core());
    const auto objs = mapObjects(m.core(), "", 5);
    const MapObject& table = *runQuery(objs, m.core().options().classes, "table with most chairs").best();
    GoalOptions o;
    o.start = kStart;
    o.keep_clear_classes = defaultKeepClearClasses(m.core().options().classes);
    const GoalPose goal = goalNextTo(table, objs, g.grid, o);
    ASSERT_TRUE(goal.found);
    mrpt::config::CConfigFile ptgs(PNDT_NAV_CONFIG);
    TpsPlannerOptions t;
    t.time_limit = 5;
    const PlannedPath path = planPathTPS(*m.getAsSimplePointsMap(), g.grid, {kStart.x(), kStart.y(), M_PI / 2},
                                         {goal.x, goal.y, goal.yaw}, ptgs, t);
    ASSERT_TRUE(path.found) << path.reason;
    std::cout << "  TP-Space RRT: " << path.points.size() << " nodes, " << path.length << " m, " << path.seconds
              << " s\n";
    EXPECT_LT((Eigen::Vector2d(path.points.back().x, path.points.back().y) - Eigen::Vector2d(goal.x, goal.y)).norm(),
              t.goal_distance + 1e-6);
    for (const auto& p : path.points) EXPECT_GE(truthClearance({p.x, p.y}), kRadius - 0.05) << p.x << " " << p.y;
}
