// Procedural indoor scenes (pndt_sim additions): determinism, class variety, sane layout.
#include <gtest/gtest.h>
#include <pndt/sim/indoor_scene.h>
#include <pndt/class_set.h>
#include <pndt/sim/nyu40_extra.h>
#include <pndt/sim/scene_objects.h>
#include <pndt/types.h>

#include <cmath>
#include <set>

using namespace pndt;
using namespace pndt::sim;

namespace
{
bool samePrimitives(const Scene& a, const Scene& b)
{
    if (a.primitives.size() != b.primitives.size()) return false;
    for (size_t i = 0; i < a.primitives.size(); ++i)
    {
        const Primitive &p = a.primitives[i], &q = b.primitives[i];
        if (p.kind != q.kind || p.center != q.center || p.half_extent != q.half_extent || p.yaw != q.yaw ||
            p.radius != q.radius || p.half_height != q.half_height || p.semantic != q.semantic ||
            p.instance != q.instance)
            return false;
    }
    return a.room.min() == b.room.min() && a.room.max() == b.room.max();
}

/// Is `p` deeper than `tol` inside primitive `q`?
bool insideDeep(const Primitive& q, const Eigen::Vector3d& p, double tol)
{
    const Eigen::Vector3d d = p - q.center;
    if (q.kind == Primitive::Kind::Cylinder)
        return d.head<2>().norm() < q.radius - tol && std::abs(d.z()) < q.half_height - tol;
    const double c = std::cos(q.yaw), s = std::sin(q.yaw);
    const Eigen::Vector3d l(c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z());
    return (l.cwiseAbs() - q.half_extent).maxCoeff() < -tol;
}

/// Samples a 5 x 5 x 5 grid inside P and tests it against Q.
bool interpenetrate(const Primitive& P, const Primitive& Q)
{
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j)
            for (int k = 0; k < 5; ++k)
            {
                const Eigen::Vector3d u((i - 2) / 2.0, (j - 2) / 2.0, (k - 2) / 2.0);  // [-1, 1]^3
                Eigen::Vector3d p;
                if (P.kind == Primitive::Kind::Cylinder)
                {
                    const double r = P.radius * std::max(std::abs(u.x()), std::abs(u.y())) * 0.999;
                    const double a = std::atan2(u.y(), u.x());
                    p = P.center + Eigen::Vector3d(r * std::cos(a), r * std::sin(a), u.z() * P.half_height * 0.999);
                }
                else
                {
                    const Eigen::Vector3d l = u.cwiseProduct(P.half_extent) * 0.999;
                    const double c = std::cos(P.yaw), s = std::sin(P.yaw);
                    p = P.center + Eigen::Vector3d(c * l.x() - s * l.y(), s * l.x() + c * l.y(), l.z());
                }
                if (insideDeep(Q, p, 0.01)) return true;
            }
    return false;
}

std::set<uint16_t> thingClasses(const Scene& s)
{
    std::set<uint16_t> c;
    for (const auto& o : sceneObjects(s)) c.insert(o.semantic);
    return c;
}
}  // namespace

TEST(IndoorScene, PresetsAreDeterministic)
{
    for (const auto& name : indoorScenePresetNames())
    {
        const Scene a = makeIndoorScene(indoorScenePreset(name));
        const Scene b = makeIndoorScene(indoorScenePreset(name));
        EXPECT_TRUE(samePrimitives(a, b)) << name;
        EXPECT_EQ(a.name, name);
    }
}

TEST(IndoorScene, DifferentSeedsGiveDifferentRooms)
{
    IndoorSceneOptions o = indoorScenePreset("living");
    const Scene a = makeIndoorScene(o);
    o.seed += 1;
    EXPECT_FALSE(samePrimitives(a, makeIndoorScene(o)));
}

TEST(IndoorScene, ManyThingClassesAndRequiredFurniture)
{
    std::set<uint16_t> all;
    for (const auto& name : indoorScenePresetNames())
    {
        const Scene s = makeIndoorScene(indoorScenePreset(name));
        const auto classes = thingClasses(s);
        EXPECT_GE(classes.size(), 9u) << name;
        EXPECT_GE(sceneObjects(s).size(), 15u) << name;
        all.insert(classes.begin(), classes.end());
    }
    namespace n = nyu40;
    for (uint16_t c : {n::kChair, n::kSofa, n::kTable,     n::kCabinet,    n::kShelves,    n::kBookshelf, n::kBed,
                       n::kLamp,  n::kDesk, n::kCounter,   n::kDoor,       n::kWindow,     n::kPicture,   n::kPillow,
                       n::kBooks, n::kBox,  n::kOtherProp, n::kTelevision, n::kNightStand, n::kCurtain})
        EXPECT_TRUE(all.count(c)) << "no " << ClassSet::nyuv2_40().name(c) << " in any preset";
    EXPECT_GE(all.size(), 25u);
}

TEST(IndoorScene, ChairsStandAroundTables)
{
    const Scene s = makeIndoorScene(indoorScenePreset("dining"));
    int chairs = 0, tables = 0;
    for (const auto& o : sceneObjects(s))
    {
        chairs += o.semantic == nyu40::kChair;
        tables += o.semantic == nyu40::kTable;
    }
    EXPECT_GE(tables, 1);
    EXPECT_GE(chairs, 3);
}

TEST(IndoorScene, ThinStructuresArePresent)
{
    // Lamp poles, plant stems and chair legs: the structures an NDT map must keep.
    const Scene s = makeIndoorScene(indoorScenePreset("living"));
    int thin_cyl = 0, thin_legs = 0;
    for (const auto& p : s.primitives)
    {
        if (p.kind == Primitive::Kind::Cylinder && p.radius <= 0.015 && p.half_height > 0.1) ++thin_cyl;
        if (p.kind == Primitive::Kind::Box && p.half_extent.x() <= 0.03 && p.half_extent.y() <= 0.03 &&
            p.half_extent.z() > 0.15)
            ++thin_legs;
    }
    EXPECT_GE(thin_cyl, 1);
    EXPECT_GE(thin_legs, 4);
}

TEST(IndoorScene, LayoutIsPhysicallyPlausible)
{
    std::vector<IndoorSceneOptions> opts;
    for (const auto& name : indoorScenePresetNames()) opts.push_back(indoorScenePreset(name));
    for (uint64_t seed = 1; seed <= 12; ++seed) opts.push_back(randomIndoorScene(seed));
    for (const auto& o : opts)
    {
        const Scene s = makeIndoorScene(o);
        const auto objects = sceneObjects(s);  // throws on mixed classes per instance
        // Instance ids 1..N, every object a thing.
        for (size_t k = 0; k < objects.size(); ++k)
        {
            EXPECT_EQ(objects[k].instance, k + 1) << s.name;
            EXPECT_TRUE(nyu40::isThing(objects[k].semantic)) << s.name;
        }
        // Everything inside the room.
        for (const auto& p : s.primitives)
        {
            const auto b = primitiveBounds(p);
            EXPECT_TRUE(s.room.contains(b.min() + Eigen::Vector3d::Constant(1e-6)) &&
                        s.room.contains(b.max() - Eigen::Vector3d::Constant(1e-6)))
                << s.name << " instance " << p.instance;
        }
        // Objects do not interpenetrate: no interior sample point of one object's
        // primitives lies inside another object's primitives (1 cm tolerance).
        for (size_t a = 0; a < s.primitives.size(); ++a)
            for (size_t b = 0; b < s.primitives.size(); ++b)
            {
                const Primitive &P = s.primitives[a], &Q = s.primitives[b];
                if (P.instance == Q.instance || !primitiveBounds(P).intersects(primitiveBounds(Q))) continue;
                EXPECT_FALSE(interpenetrate(P, Q))
                    << s.name << ": objects " << P.instance << " (" << ClassSet::nyuv2_40().name(P.semantic) << ") and "
                    << Q.instance << " (" << ClassSet::nyuv2_40().name(Q.semantic) << ") interpenetrate";
            }
    }
}

TEST(IndoorScene, ScenesDifferInSizeAndClutter)
{
    const Scene small = makeIndoorScene(indoorScenePreset("small"));
    const Scene hall = makeIndoorScene(indoorScenePreset("hall"));
    EXPECT_GT(hall.room.volume(), 4 * small.room.volume());
    EXPECT_GT(sceneObjects(hall).size(), 2 * sceneObjects(small).size());
}

TEST(IndoorScene, BadOptionsThrow)
{
    IndoorSceneOptions o;
    o.room_size = {2.0, 5.0, 2.6};
    EXPECT_THROW(makeIndoorScene(o), InputError);
    o = {};
    o.clutter = 1.5;
    EXPECT_THROW(makeIndoorScene(o), InputError);
    try
    {
        indoorScenePreset("castle");
        FAIL();
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("castle"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("small"), std::string::npos);
    }
}
