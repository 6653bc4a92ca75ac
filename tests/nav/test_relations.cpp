// Footprints and spatial relations on hand-made objects, against hand-computed values.
#include <gtest/gtest.h>
#include <pndt/nav/spatial_relations.h>

#include <cmath>

using namespace pndt::nav;

namespace
{
MapObject object(uint32_t id, int cls, Eigen::Vector2d c, Eigen::Vector2d half, double z0, double z1, uint32_t voxels = 100,
                 double yaw = 0)
{
    MapObject o;
    o.id = id;
    o.class_id = uint16_t(cls);
    o.voxel_count = voxels;
    o.footprint.center = c;
    o.footprint.half_size = half;
    o.footprint.yaw = yaw;
    o.z_min = z0;
    o.z_max = z1;
    o.centroid = Eigen::Vector3d(c.x(), c.y(), 0.5 * (z0 + z1));
    return o;
}
constexpr int kChair = 5, kTable = 7, kLamp = 35;
}  // namespace

TEST(Footprint, DistancesByHand)
{
    Footprint a, b;
    a.half_size = {1, 0.5};
    b.center = {3, 0};
    b.half_size = {1, 0.5};
    EXPECT_NEAR(footprintDistance(a, b), 1.0, 1e-12);  // facing edges at x = 1 and x = 2
    b.center = {3, 2};
    EXPECT_NEAR(footprintDistance(a, b), std::hypot(1.0, 1.0), 1e-12);  // corner to corner
    // Turned 45 deg: its corner points at a, sqrt(2)*0.5 from its centre.
    b.center = {2.5, 0};
    b.half_size = {0.5, 0.5};
    b.yaw = M_PI / 4;
    EXPECT_NEAR(footprintDistance(a, b), 1.5 - std::sqrt(0.5), 1e-12);
    // A long thin bar across a's corner region, no corner inside either: overlap.
    Footprint bar;
    bar.center = {1, 0.5};
    bar.half_size = {2, 0.05};
    bar.yaw = M_PI / 4;
    EXPECT_EQ(footprintDistance(a, bar), 0.0);
    EXPECT_NEAR(a.distanceTo({2, 1.5}), std::hypot(1.0, 1.0), 1e-12);
    EXPECT_EQ(a.distanceTo({0.5, 0.2}), 0.0);
}

TEST(Footprint, MinAreaRectangleOfATurnedBox)
{
    // Points on the four edges of a 2 x 1 box turned by 30 degrees around (1, 2):
    // local (u, +-0.5) on the long edges, (+-1, u/2) on the short ones.
    std::vector<Eigen::Vector2d> pts;
    const double yaw = M_PI / 6, c = std::cos(yaw), s = std::sin(yaw);
    for (double u = -1; u <= 1.0001; u += 0.25)
        for (double v : {-0.5, 0.5})
        {
            pts.emplace_back(1 + c * u - s * v, 2 + s * u + c * v);
            pts.emplace_back(1 + c * v * 2 - s * u / 2, 2 + s * v * 2 + c * u / 2);
        }
    const Footprint f = minAreaFootprint(pts, 0.05);
    EXPECT_NEAR(f.center.x(), 1, 1e-9);
    EXPECT_NEAR(f.center.y(), 2, 1e-9);
    EXPECT_NEAR(f.half_size.x(), 1.05, 1e-9);
    EXPECT_NEAR(f.half_size.y(), 0.55, 1e-9);
    EXPECT_NEAR(std::remainder(f.yaw - yaw, M_PI), 0, 1e-9);
    EXPECT_THROW(minAreaFootprint({}, 0), std::invalid_argument);
}

TEST(Relations, ChairsAroundTablesCountedOnceEachAndFragmentsAsOne)
{
    std::vector<MapObject> objs{
        object(1, kTable, {0, 0}, {0.8, 0.45}, 0, 0.75),
        object(2, kTable, {3, 0}, {0.5, 0.5}, 0, 0.75),
        object(10, kChair, {0, 0.8}, {0.225, 0.225}, 0, 0.9),    // north of table 1
        object(11, kChair, {0, -0.8}, {0.225, 0.225}, 0, 0.9),   // south
        object(12, kChair, {-1.15, 0}, {0.225, 0.225}, 0, 0.9),  // west: its seat ...
        object(13, kChair, {-1.33, 0}, {0.02, 0.225}, 0.45, 0.9, 150),  // ... and back, a second instance
        object(14, kChair, {1.6, 0}, {0.225, 0.225}, 0, 0.9),    // between: 0.575 from table 1, 0.975 from table 2
        object(15, kChair, {3.85, 0}, {0.225, 0.225}, 0, 0.9),   // east of table 2
        object(16, kChair, {6, 0}, {0.225, 0.225}, 0, 0.9),      // far from both
        object(20, kLamp, {3, 0.2}, {0.1, 0.1}, 0.76, 1.2),      // on table 2
    };
    EXPECT_TRUE(areFragmentsOfOne(objs[4], objs[5]));
    EXPECT_FALSE(areFragmentsOfOne(objs[2], objs[3]));
    const auto around = objectsAround(objs, kTable, kChair);
    EXPECT_EQ(around.at(1), (std::vector<uint32_t>{10, 11, 13, 14}));  // 12+13 once, as the larger piece
    EXPECT_EQ(around.at(2), (std::vector<uint32_t>{15}));
    EXPECT_TRUE(isOnTopOf(objs[9], objs[1]));
    EXPECT_FALSE(isOnTopOf(objs[9], objs[0]));
    EXPECT_FALSE(isOnTopOf(objs[2], objs[0]));
    EXPECT_TRUE(isNextTo(objs[2], objs[0]));     // 0.125 m apart
    EXPECT_FALSE(isNextTo(objs[8], objs[1]));    // 2.775 m apart
    EXPECT_FALSE(isNextTo(objs[9], objs[1]));    // on it, not next to it
    const auto near = nearestTo(objs, kChair, {2.0, 0});
    EXPECT_EQ(near.front().first->id, 14u);
    EXPECT_NEAR(near.front().second, 2.0 - 1.825, 1e-12);
}
