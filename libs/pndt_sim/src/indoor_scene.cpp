// makeIndoorScene: procedural furnished rooms (see indoor_scene.h).
//
// Placement works on world AABBs: every placed object (and the walkway in front of
// the door) reserves its box; a new object is accepted only if its box, grown by a
// small margin in x/y, meets no reserved box. Wall-mounted items reserve their thin
// box at their height, so low furniture may stand under a window but a bookshelf
// may not cover a picture. Small objects are placed afterwards on the top faces
// ("surfaces") of tables, desks, cabinets and shelf boards.
//
// Random draws are never two arguments of one call: C++ leaves the order in which
// arguments are evaluated open (GCC goes right to left, clang left to right), and a
// clang build made other rooms from the same seed. Each draw is a named local, in
// the order GCC drew them, so the documented scenes stay what they were.
#include "pndt/sim/indoor_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>

#include "pndt/sim/furniture.h"
#include "pndt/sim/nyu40_extra.h"
#include "pndt/sim/trajectory.h"
#include "pndt/types.h"
#include "primitive_geometry.h"
#include "sim_random.h"

namespace pndt::sim
{
namespace
{
using detail::SimRng;
using Box3 = Eigen::AlignedBox3d;

/// World point of a local offset in a placement's frame.
Eigen::Vector3d localToWorld(const Placement& p, const Eigen::Vector3d& l)
{
    double c, s;
    detail::exactCosSin(p.yaw, c, s);
    return p.base + Eigen::Vector3d(c * l.x() - s * l.y(), s * l.x() + c * l.y(), l.z());
}

Placement child(const Placement& parent, const Eigen::Vector3d& local, double dyaw = 0)
{
    return {localToWorld(parent, local), parent.yaw + dyaw};
}

/// AABB of an object of local size (x, y, z) standing at p (any yaw).
Box3 objectBox(const Placement& p, const Size3& size)
{
    double c, s;
    detail::exactCosSin(p.yaw, c, s);
    const double ex = 0.5 * (std::abs(c) * size.x() + std::abs(s) * size.y());
    const double ey = 0.5 * (std::abs(s) * size.x() + std::abs(c) * size.y());
    return Box3(Eigen::Vector3d(p.base.x() - ex, p.base.y() - ey, p.base.z()),
                Eigen::Vector3d(p.base.x() + ex, p.base.y() + ey, p.base.z() + size.z()));
}

struct Layout
{
    Box3 room;
    std::vector<Box3> taken;

    bool fits(const Box3& b, double margin) const
    {
        constexpr double eps = 1e-9;
        for (int i = 0; i < 2; ++i)
            if (b.min()[i] < room.min()[i] - eps || b.max()[i] > room.max()[i] + eps) return false;
        if (b.max().z() > room.max().z() + eps) return false;
        for (const Box3& t : taken)
        {
            const bool overlap = b.min().x() < t.max().x() + margin && b.max().x() > t.min().x() - margin &&
                                 b.min().y() < t.max().y() + margin && b.max().y() > t.min().y() - margin &&
                                 b.min().z() < t.max().z() && b.max().z() > t.min().z();
            if (overlap) return false;
        }
        return true;
    }
    bool tryTake(const Box3& b, double margin)
    {
        if (!fits(b, margin)) return false;
        taken.push_back(b);
        return true;
    }
};

struct WallFrame
{
    Eigen::Vector2d origin, tangent, inward;
    double length = 0, yaw = 0;
};

/// Wall 0: x = max, 1: y = max, 2: x = min, 3: y = min. `inward` points into the room;
/// yaw makes an object's local +x point inward.
WallFrame wallFrame(const Box3& room, int wall)
{
    const Eigen::Vector3d c = room.center(), e = 0.5 * room.sizes();
    WallFrame w;
    switch (wall & 3)
    {
        case 0:
            w.origin = {c.x() + e.x(), c.y()};
            w.inward = {-1, 0};
            w.length = 2 * e.y();
            break;
        case 1:
            w.origin = {c.x(), c.y() + e.y()};
            w.inward = {0, -1};
            w.length = 2 * e.x();
            break;
        case 2:
            w.origin = {c.x() - e.x(), c.y()};
            w.inward = {1, 0};
            w.length = 2 * e.y();
            break;
        default:
            w.origin = {c.x(), c.y() - e.y()};
            w.inward = {0, 1};
            w.length = 2 * e.x();
            break;
    }
    w.tangent = {-w.inward.y(), w.inward.x()};
    w.yaw = std::atan2(w.inward.y(), w.inward.x());
    return w;
}

Placement wallPlacement(const WallFrame& w, double u, double depth, double z, double gap)
{
    const Eigen::Vector2d xy = w.origin + u * w.tangent + (0.5 * depth + gap) * w.inward;
    return {Eigen::Vector3d(xy.x(), xy.y(), z), w.yaw};
}

/// A horizontal top face small objects may stand on: centre, yaw, half sizes, headroom.
struct Surface
{
    Placement top;
    double hx = 0, hy = 0, headroom = 0.5;
    std::vector<Eigen::AlignedBox2d> used;  // local footprints already taken
};

struct Ctx
{
    Scene& s;
    Layout L;
    SimRng rng;
    double clutter = 0.5;
    RoomType type = RoomType::Living;
    uint32_t next_id = 1;
    std::vector<Surface> surfaces;  // tables, cabinets, top boards
    std::vector<Surface> boards;    // shelf boards (books)

    uint32_t id() { return next_id++; }
    int count(double base, double per_clutter)
    {
        return std::max(0, static_cast<int>(std::floor(base + per_clutter * clutter + rng.uniform())));
    }
    double area() const { return L.room.sizes().x() * L.room.sizes().y(); }
};

/// Tries `tries` random wall positions; on success reserves the box and returns the placement.
std::optional<Placement> tryWall(Ctx& c, const Size3& size, double z0, double gap, double margin, int wall = -1,
                                 int tries = 40)
{
    for (int t = 0; t < tries; ++t)
    {
        int w = wall;
        if (w < 0)
        {
            const double lx = c.L.room.sizes().y(), ly = c.L.room.sizes().x();
            const double u = c.rng.uniform() * 2 * (lx + ly);
            w = u < lx ? 0 : u < lx + ly ? 1 : u < 2 * lx + ly ? 2 : 3;
        }
        const WallFrame f = wallFrame(c.L.room, w);
        const double half_free = 0.5 * f.length - 0.5 * size.y() - 0.02;
        if (half_free < 0) continue;
        const double u = c.rng.uniform(-half_free, half_free);
        const Placement p = wallPlacement(f, u, size.x(), z0, gap);
        if (c.L.tryTake(objectBox(p, size), margin)) return p;
    }
    return std::nullopt;
}

std::optional<Placement> tryAt(Ctx& c, const Placement& p, const Size3& size, double margin)
{
    if (c.L.tryTake(objectBox(p, size), margin)) return p;
    return std::nullopt;
}

/// Keeps the floor in front of an object (its local +x side) free of later furniture:
/// a walkway / access zone `depth` deep, as wide as the object plus `extra` each side.
void reserveFront(Ctx& c, const Placement& p, const Size3& size, double depth, double extra = 0.0)
{
    const Placement z = child(p, {0.5 * size.x() + 0.5 * depth, 0, 0});
    c.L.taken.push_back(objectBox(z, Size3(depth, size.y() + 2 * extra, 1.2)));
}

/// Reserves a ring `walk` wide around a box (a walkway round a table group).
void reserveAround(Ctx& c, const Box3& b, double walk)
{
    Box3 z = b;
    z.min() -= Eigen::Vector3d(walk, walk, 0);
    z.max() += Eigen::Vector3d(walk, walk, 0);
    z.min().z() = c.L.room.min().z();
    z.max().z() = c.L.room.min().z() + 1.2;
    c.L.taken.push_back(z);
}

/// The free position nearest to `preferred` (10 cm grid) where an object of `size` and
/// `yaw` fits with `margin`; nullopt if none.
std::optional<Eigen::Vector2d> findSpot(const Ctx& c, const Eigen::Vector2d& preferred, double yaw, const Size3& size,
                                        double margin)
{
    std::optional<Eigen::Vector2d> best;
    double best_d = 1e18;
    const Eigen::Vector3d lo = c.L.room.min(), hi = c.L.room.max();
    for (double x = lo.x(); x <= hi.x(); x += 0.1)
        for (double y = lo.y(); y <= hi.y(); y += 0.1)
        {
            const Eigen::Vector2d p(x, y);
            const double d = (p - preferred).squaredNorm();
            if (d >= best_d) continue;
            if (!c.L.fits(objectBox({Eigen::Vector3d(x, y, lo.z()), yaw}, size), margin)) continue;
            best_d = d;
            best = p;
        }
    return best;
}

void addSurface(Ctx& c, const Placement& obj, const Size3& size, double headroom, std::vector<Surface>* list = nullptr)
{
    Surface s;
    s.top = {localToWorld(obj, {0, 0, size.z()}), obj.yaw};
    s.hx = 0.5 * size.x() - 0.04;
    s.hy = 0.5 * size.y() - 0.04;
    s.headroom = headroom;
    if (s.hx > 0.05 && s.hy > 0.05) (list ? *list : c.surfaces).push_back(s);
}

/// Finds a free spot of local footprint (dx, dy) on a surface.
std::optional<Placement> spotOn(Ctx& c, Surface& s, double dx, double dy, int tries = 12)
{
    if (dx > 2 * s.hx || dy > 2 * s.hy) return std::nullopt;
    for (int t = 0; t < tries; ++t)
    {
        const double x = c.rng.uniform(-s.hx + 0.5 * dx, s.hx - 0.5 * dx);
        const double y = c.rng.uniform(-s.hy + 0.5 * dy, s.hy - 0.5 * dy);
        const Eigen::AlignedBox2d fp(Eigen::Vector2d(x - 0.5 * dx - 0.02, y - 0.5 * dy - 0.02),
                                     Eigen::Vector2d(x + 0.5 * dx + 0.02, y + 0.5 * dy + 0.02));
        bool free = true;
        for (const auto& u : s.used)
            if (u.intersects(fp)) free = false;
        if (!free) continue;
        s.used.push_back(fp);
        return child(s.top, {x, y, 0});
    }
    return std::nullopt;
}

// --- wall features --------------------------------------------------------------------

void addDoorsAndWindows(Ctx& c, int doors, int windows)
{
    const double H = c.L.room.sizes().z();
    for (int d = 0; d < doors; ++d)
    {
        const Size3 door(0.04, 0.9, std::min(2.05, H - 0.15));
        if (auto p = tryWall(c, door, 0.0, 0.0, 0.1))
        {
            addWallPanel(c.s, *p, c.id(), door, nyu40::kDoor);
            // Walkway in front of the door stays free.
            c.L.taken.push_back(objectBox(child(*p, {0.5, 0, 0}), Size3(1.0, 1.1, door.z())));
        }
    }
    for (int w = 0; w < windows; ++w)
    {
        const double bottom = 0.9, height = std::min(1.3, H - bottom - 0.3);
        const Size3 win(0.03, c.rng.uniform(0.9, 1.6), height);
        const bool curtains = c.rng.chance(0.5);
        const Size3 span(win.x(), win.y() + (curtains ? 0.8 : 0.0), win.z());
        auto p = tryWall(c, span, bottom, 0.0, 0.1);
        if (!p) continue;
        addWallPanel(c.s, *p, c.id(), win, nyu40::kWindow);
        if (curtains)
        {
            const double top = std::min(H - 0.05, bottom + height + 0.25);
            const Size3 cur(0.05, 0.35, top - 0.05);
            for (double side : {1.0, -1.0})
            {
                const Placement cp = child(*p, {0.045, side * (0.5 * win.y() + 0.2), 0.0});
                Placement q{Eigen::Vector3d(cp.base.x(), cp.base.y(), 0.05), cp.yaw};
                if (c.L.tryTake(objectBox(q, cur), 0.0)) addWallPanel(c.s, q, c.id(), cur, nyu40::kCurtain);
            }
        }
    }
}

void addPictures(Ctx& c, int n)
{
    for (int k = 0; k < n; ++k)
    {
        const bool board = c.type == RoomType::Office && k == 0;
        Size3 size(0.02, 1.5, 1.0);
        if (!board)
        {
            const double sz = c.rng.uniform(0.3, 0.7), sy = c.rng.uniform(0.35, 0.9);
            size = Size3(0.025, sy, sz);
        }
        const double z0 = board ? 0.95 : c.rng.uniform(1.25, 1.5);
        if (z0 + size.z() > c.L.room.sizes().z() - 0.1) continue;
        if (auto p = tryWall(c, size, z0, 0.0, 0.1))
            addWallPanel(c.s, *p, c.id(), size, board ? nyu40::kWhiteboard : nyu40::kPicture);
    }
}

// --- furniture groups -----------------------------------------------------------------

bool addSofaGroup(Ctx& c)
{
    const double w = c.rng.uniform(1.7, 2.2);
    const Size3 sofa(0.95, w, 0.85);
    auto sp = tryWall(c, sofa, 0.0, 0.02, 0.1);
    if (!sp) return false;
    addSofa(c.s, *sp, c.id(), w);
    // Pillows leaning on the back cushion, between the arms.
    const int pillows = std::min(c.count(1.0, 2.0), static_cast<int>((w - 0.36 - 0.05) / 0.47));
    for (int k = 0; k < pillows; ++k)
    {
        const double y = (k - 0.5 * (pillows - 1)) * 0.47;
        addBlock(c.s, child(*sp, {-0.13, y, 0.42}, c.rng.uniform(-0.1, 0.1)), c.id(), Size3(0.12, 0.42, 0.38),
                 nyu40::kPillow);
    }
    // Coffee table in front; optional rug under it.
    const Size3 table(0.6, 1.1, 0.45);
    const Placement tp = child(*sp, {0.475 + 0.45 + 0.3, 0, 0});
    if (c.rng.chance(0.5))
    {
        const Placement rug = child(*sp, {1.1, 0, 0});
        const Size3 rs(1.4, std::min(2.2, w + 0.2), 0.01);
        const Box3 rb = objectBox(rug, rs);
        if (c.L.room.contains(rb.min()) && c.L.room.contains(rb.max()))
            addBlock(c.s, rug, c.id(), rs, nyu40::kFloorMat);
    }
    if (tryAt(c, tp, table, 0.05))
    {
        addTable(c.s, tp, c.id(), table, nyu40::kTable, 0.05);
        addSurface(c, tp, table, 0.5);
    }
    // Armchairs beside or across the coffee table, facing it.
    const int chairs = std::min(2, c.count(0.8, 1.2));
    int placed = 0;
    const std::array<std::pair<Eigen::Vector3d, double>, 4> spots = {{
        {{1.2, 0.55 + 0.5, 0}, -M_PI_2},
        {{1.2, -(0.55 + 0.5), 0}, M_PI_2},
        {{1.2 + 0.3 + 0.55, 0.35, 0}, M_PI},
        {{1.2 + 0.3 + 0.55, -0.35, 0}, M_PI},
    }};
    for (const auto& [pos, yaw] : spots)
    {
        if (placed >= chairs) break;
        const Placement ap = child(*sp, pos, yaw);
        if (tryAt(c, ap, Size3(0.8, 0.8, 0.9), 0.05))
        {
            addArmchair(c.s, ap, c.id());
            ++placed;
        }
    }
    reserveFront(c, *sp, Size3(0.95 + 0.45 + 0.6 + 0.45, w, 0.85), 0.6, 0.3);
    // Side table with a lamp next to the sofa.
    if (c.rng.chance(0.3 + 0.6 * c.clutter))
    {
        const Size3 st(0.45, 0.45, 0.55);
        const double side = c.rng.chance(0.5) ? 1.0 : -1.0;
        const Placement p = child(*sp, {-0.2, side * (0.5 * w + 0.3), 0});
        if (tryAt(c, p, st, 0.02))
        {
            addTable(c.s, p, c.id(), st, nyu40::kTable, 0.04);
            addTableLamp(c.s, child(p, {0, 0, st.z()}), c.id());
        }
    }
    return true;
}

bool addTvStand(Ctx& c)
{
    const Size3 stand(0.45, c.rng.uniform(1.2, 1.6), 0.5);
    auto p = tryWall(c, stand, 0.0, 0.02, 0.1);
    if (!p) return false;
    addCabinet(c.s, *p, c.id(), stand, nyu40::kCabinet, 2);
    reserveFront(c, *p, stand, 0.7);
    addMonitor(c.s, child(*p, {-0.05, 0, stand.z()}), c.id(), c.rng.uniform(0.9, 1.2));
    Surface s;
    s.top = child(*p, {0.12, 0, stand.z()});
    s.hx = 0.08;
    s.hy = 0.5 * stand.y() - 0.05;
    c.surfaces.push_back(s);
    return true;
}

void addStorage(Ctx& c, int n)
{
    for (int k = 0; k < n; ++k)
    {
        const int kind = c.rng.below(5);
        if (kind == 0 || kind == 1)  // shelves / bookshelf
        {
            const bool book = kind == 0;
            const double sz = book ? c.rng.uniform(1.6, 2.0) : c.rng.uniform(0.9, 1.3), sy = c.rng.uniform(0.8, 1.3);
            const Size3 size(0.35, sy, sz);
            auto p = tryWall(c, size, 0.0, 0.02, 0.1);
            if (!p) continue;
            std::vector<double> tops;
            const int boards = book ? 5 : 3;
            addShelves(c.s, *p, c.id(), size, boards, book, book ? nyu40::kBookshelf : nyu40::kShelves, &tops);
            reserveFront(c, *p, size, 0.5);
            const double spacing = (size.z() - 0.085) / (boards - 1);
            for (size_t b = 0; b + 1 < tops.size(); ++b)
            {
                Surface s;
                s.top = child(*p, {0, 0, tops[b]});
                s.hx = 0.5 * size.x() - 0.03;
                s.hy = 0.5 * size.y() - 0.05;
                s.headroom = spacing - 0.03;
                c.boards.push_back(s);
            }
            addSurface(c, child(*p, {0, 0, 0}), Size3(size.x(), size.y() - 0.04, tops.back()), 0.4);
        }
        else if (kind == 2)  // low cabinet / dresser
        {
            const bool dresser = c.type == RoomType::Bedroom && c.rng.chance(0.6);
            const Size3 size(0.5, c.rng.uniform(0.8, 1.2), dresser ? 0.85 : 0.75);
            auto p = tryWall(c, size, 0.0, 0.02, 0.1);
            if (!p) continue;
            addCabinet(c.s, *p, c.id(), size, dresser ? nyu40::kDresser : nyu40::kCabinet, dresser ? 3 : 2);
            reserveFront(c, *p, size, 0.5);
            addSurface(c, *p, size, 0.5);
        }
        else if (kind == 3)  // tall cabinet / wardrobe
        {
            const Size3 size(0.6, c.rng.uniform(0.9, 1.3), std::min(2.0, c.L.room.sizes().z() - 0.2));
            auto p = tryWall(c, size, 0.0, 0.02, 0.1);
            if (!p) continue;
            addCabinet(c.s, *p, c.id(), size, nyu40::kCabinet, 2);
            reserveFront(c, *p, size, 0.6);
        }
        else  // other furniture: a bench / chest
        {
            const Size3 size(0.45, c.rng.uniform(0.8, 1.4), 0.45);
            auto p = tryWall(c, size, 0.0, 0.02, 0.1);
            if (!p) continue;
            addBlock(c.s, *p, c.id(), size, nyu40::kOtherFurniture);
            reserveFront(c, *p, size, 0.4);
            addSurface(c, *p, size, 0.4);
        }
    }
}

/// Table with chairs round it, as near to `center` as the free floor allows (the group
/// keeps a walkway round it).
bool addDiningGroup(Ctx& c, const Eigen::Vector2d& center, double yaw, bool allow_round)
{
    const bool round = allow_round && c.rng.chance(0.35);
    constexpr double kWalk = 0.5, kChairReach = 0.6;
    const double r = c.rng.uniform(0.45, 0.6);
    const double sy = c.rng.uniform(1.4, 1.9), sx = c.rng.uniform(0.8, 1.0);
    const Size3 size(sx, sy, 0.75);
    const Size3 group_size = round ? Size3(2 * (r + kChairReach), 2 * (r + kChairReach), 0.9)
                                   : Size3(size.x() + 2 * kChairReach, size.y() + 2 * kChairReach, 0.9);
    const auto spot = findSpot(c, center, yaw, group_size, kWalk);
    if (!spot) return false;
    // The whole group box is free (with a walkway round it), so table and chairs go in
    // without further checks; their spacing keeps them apart.
    const Placement tp{Eigen::Vector3d(spot->x(), spot->y(), c.L.room.min().z()), yaw};
    const Box3 group = objectBox(tp, group_size);
    if (round)
    {
        addRoundTable(c.s, tp, c.id(), r, 0.75);
        Surface s;
        s.top = child(tp, {0, 0, 0.75});
        s.hx = s.hy = 0.6 * r;
        c.surfaces.push_back(s);
        const int n = 3 + c.rng.below(3);
        const double a0 = c.rng.uniform(0, kTwoPi);
        for (int k = 0; k < n; ++k)
        {
            const double a = a0 + k * kTwoPi / n;
            addChair(c.s, {tp.base + Eigen::Vector3d((r + 0.28) * std::cos(a), (r + 0.28) * std::sin(a), 0), a + M_PI},
                     c.id());
        }
    }
    else
    {
        addTable(c.s, tp, c.id(), size, nyu40::kTable, 0.06);
        addSurface(c, tp, size, 0.5);
        // Chairs along both long sides (+ maybe one end), facing the table.
        const int per_side = size.y() > 1.6 ? 3 : 2;
        for (double side : {1.0, -1.0})
            for (int k = 0; k < per_side; ++k)
            {
                if (!c.rng.chance(0.85)) continue;
                const double y = (k - 0.5 * (per_side - 1)) * size.y() / per_side;
                addChair(c.s, child(tp, {side * (0.5 * size.x() + 0.27), y, 0}, side > 0 ? M_PI : 0.0), c.id());
            }
        if (c.rng.chance(0.5)) addChair(c.s, child(tp, {0, 0.5 * size.y() + 0.3, 0}, -M_PI_2), c.id());
    }
    c.L.taken.push_back(group);
    reserveAround(c, group, kWalk);
    return true;
}

void addDesks(Ctx& c, int n)
{
    for (int k = 0; k < n; ++k)
    {
        const Size3 size(0.7, c.rng.uniform(1.2, 1.6), 0.74);
        auto p = tryWall(c, size, 0.0, 0.02, 0.1);
        if (!p) continue;
        addDesk(c.s, *p, c.id(), size);
        // Checked as a desk-aligned 0.75 m square (the chair itself is turned a little).
        const Placement cp = child(*p, {0.5 * size.x() + 0.4, c.rng.uniform(-0.2, 0.2), 0}, M_PI);
        if (c.L.tryTake(objectBox(cp, Size3(0.75, 0.75, 1.1)), 0.02))
            addOfficeChair(c.s, {cp.base, cp.yaw + c.rng.uniform(-0.4, 0.4)}, c.id());
        reserveFront(c, *p, Size3(size.x() + 0.7, size.y(), size.z()), 0.5);
        Surface s;
        s.top = child(*p, {0, 0, size.z()});
        s.hx = 0.5 * size.x() - 0.05;
        s.hy = 0.5 * size.y() - 0.05;
        if (c.type == RoomType::Office || c.rng.chance(0.5))
        {
            auto m = spotOn(c, s, 0.2, 0.6);
            if (m) addMonitor(c.s, child(*m, {0, 0, 0}, c.rng.uniform(-0.3, 0.3)), c.id(), 0.55);
        }
        c.surfaces.push_back(s);
        if (c.rng.chance(0.5))  // waste bin beside the desk
        {
            const Placement bp = child(*p, {0.1, -(0.5 * size.y() + 0.25), 0});
            if (tryAt(c, bp, Size3(0.3, 0.3, 0.35), 0.02)) addCylinderObject(c.s, bp, c.id(), 0.14, 0.35);
        }
    }
}

bool addKitchenRun(Ctx& c)
{
    // Longest wall first.
    const int wall =
        c.L.room.sizes().y() >= c.L.room.sizes().x() ? (c.rng.chance(0.5) ? 0 : 2) : (c.rng.chance(0.5) ? 1 : 3);
    const double len = std::min(2.6, wallFrame(c.L.room, wall).length - 1.2);
    if (len < 1.2) return false;
    const Size3 base(0.6, len, 0.86);
    auto p = tryWall(c, base, 0.0, 0.0, 0.05, wall);
    if (!p) return false;
    addCabinet(c.s, *p, c.id(), base, nyu40::kCabinet, std::max(2, int(len / 0.6)));
    const Size3 top(0.63, len + 0.02, 0.04);
    addBlock(c.s, child(*p, {0.015, 0, base.z()}), c.id(), top, nyu40::kCounter);
    c.L.taken.push_back(objectBox(child(*p, {0.015, 0, base.z()}), top));
    addSurface(c, child(*p, {0.015, 0, 0}), Size3(top.x(), top.y(), base.z() + top.z()), 0.5);
    reserveFront(c, *p, base, 0.8);
    const Size3 upper(0.35, len, 0.7);
    const Placement up = child(*p, {-0.125, 0, 1.45});
    if (1.45 + upper.z() < c.L.room.sizes().z() - 0.05 && tryAt(c, up, upper, 0.0))
        addCabinet(c.s, up, c.id(), upper, nyu40::kCabinet, std::max(2, int(len / 0.6)));
    // Fridge at one end.
    const Size3 fr(0.7, 0.72, 1.8);
    for (double side : {1.0, -1.0})
    {
        const Placement fp = child(*p, {0.05, side * (0.5 * len + 0.4), 0});
        if (tryAt(c, fp, fr, 0.02))
        {
            addCabinet(c.s, fp, c.id(), fr, nyu40::kRefrigerator, 1);
            break;
        }
    }
    return true;
}

bool addBedGroup(Ctx& c)
{
    const double w = c.rng.uniform(1.4, 1.7), l = 2.05;
    const Size3 bed(l, w, 0.55);
    // Night stands either side: reserve the full span.
    auto p = tryWall(c, Size3(l, w + 1.0, 0.6), 0.0, 0.02, 0.05);
    const bool wide = p.has_value();
    if (!p) p = tryWall(c, bed, 0.0, 0.02, 0.05);
    if (!p) return false;
    addBed(c.s, *p, c.id(), bed);
    reserveFront(c, *p, bed, 0.6, 0.3);
    for (double side : {1.0, -1.0})
        addBlock(c.s, child(*p, {-0.5 * l + 0.3, side * 0.33, bed.z()}, c.rng.uniform(-0.15, 0.15)), c.id(),
                 Size3(0.35, 0.55, 0.14), nyu40::kPillow);
    if (c.rng.chance(0.5))
    {
        const double yaw = c.rng.uniform(-0.5, 0.5), y = c.rng.uniform(-0.3, 0.3);
        addBlock(c.s, child(*p, {0.5 * l - 0.4, y, bed.z()}, yaw), c.id(),
                 Size3(0.4, 0.5, 0.06), nyu40::kClothes);
    }
    const Size3 ns(0.42, 0.45, 0.5);
    for (double side : {1.0, -1.0})
    {
        const Placement np = child(*p, {-0.5 * l + 0.5 * ns.x(), side * (0.5 * w + 0.05 + 0.5 * ns.y()), 0});
        const Box3 nb = objectBox(np, ns);
        if (!(c.L.room.contains(nb.min()) && c.L.room.contains(nb.max()))) continue;
        if (!wide && !c.L.tryTake(nb, 0.0)) continue;
        addCabinet(c.s, np, c.id(), ns, nyu40::kNightStand, 1);
        addTableLamp(c.s, child(np, {-0.05, 0, ns.z()}), c.id());
    }
    return true;
}

void addDecor(Ctx& c, int plants, int floor_lamps, int bags, int poles)
{
    for (int k = 0; k < plants; ++k)
    {
        const double h = c.rng.uniform(0.7, 1.4);
        if (auto p = tryWall(c, Size3(0.6, 0.6, h), 0.0, 0.02, 0.05)) addPlant(c.s, *p, c.id(), h);
    }
    for (int k = 0; k < floor_lamps; ++k)
    {
        const double h = std::min(1.7, c.L.room.sizes().z() - 0.2);
        if (auto p = tryWall(c, Size3(0.4, 0.4, h), 0.0, 0.05, 0.05)) addFloorLamp(c.s, *p, c.id(), h);
    }
    for (int k = 0; k < bags; ++k)
    {
        const Size3 size(0.2, 0.35, 0.4);
        // Reserve the footprint of the bag turned by up to 0.5 rad.
        if (auto p = tryWall(c, Size3(0.45, 0.45, 0.4), 0.0, 0.02, 0.05))
        {
            const auto cls = c.rng.chance(0.6) ? nyu40::kBag : nyu40::kBox;
            const double yaw = c.rng.uniform(-0.5, 0.5);
            addBlock(c.s, child(*p, {0, 0, 0}, yaw), c.id(), size, cls);
        }
    }
    const double H = c.L.room.sizes().z();
    for (int k = 0; k < poles; ++k)
    {
        // Thin pipe a little off a wall (radius 2-4 cm), floor to ceiling.
        const double r = c.rng.uniform(0.02, 0.04);
        if (auto p = tryWall(c, Size3(2 * r, 2 * r, H), 0.0, 0.12, 0.1)) addPole(c.s, *p, c.id(), r, H);
    }
}

void addSmallObjects(Ctx& c, int n)
{
    // Book rows on shelf boards.
    for (Surface& b : c.boards)
    {
        if (!c.rng.chance(0.35 + 0.5 * c.clutter)) continue;
        const int count = 3 + c.rng.below(8);
        std::vector<double> var(static_cast<size_t>(2 * count));
        for (double& v : var) v = c.rng.uniform();
        if (auto p = spotOn(c, b, 0.2, 0.035 * count + 0.02)) addBookRow(c.s, *p, c.id(), count, var);
        if (c.rng.chance(0.3))
            if (auto q = spotOn(c, b, 0.2, 0.2))
                addBlock(c.s, *q, c.id(), Size3(0.2, 0.2, std::min(0.18, b.headroom)), nyu40::kBox);
    }
    if (c.surfaces.empty()) return;
    for (int k = 0; k < n; ++k)
    {
        Surface& s = c.surfaces[static_cast<size_t>(c.rng.below(static_cast<int>(c.surfaces.size())))];
        const int kind = c.rng.below(7);
        const double yaw = c.rng.uniform(-M_PI, M_PI);
        switch (kind)
        {
            case 0:
                if (auto p = spotOn(c, s, 0.1, 0.1)) addCylinderObject(c.s, *p, c.id(), 0.04, 0.1);  // cup
                break;
            case 1:
                if (auto p = spotOn(c, s, 0.08, 0.08))
                    addCylinderObject(c.s, *p, c.id(), 0.035, std::min(0.3, s.headroom));  // bottle
                break;
            case 2:
            {
                const double bz = std::min(s.headroom, c.rng.uniform(0.08, 0.25)), by = c.rng.uniform(0.12, 0.3),
                             bx = c.rng.uniform(0.12, 0.3);
                const Size3 b(bx, by, bz);
                if (auto p = spotOn(c, s, std::max(b.x(), b.y()) * 1.42, std::max(b.x(), b.y()) * 1.42))
                    addBlock(c.s, child(*p, {0, 0, 0}, yaw), c.id(), b, nyu40::kBox);
                break;
            }
            case 3:
                if (auto p = spotOn(c, s, 0.33, 0.33))
                    addBlock(c.s, child(*p, {0, 0, 0}, yaw), c.id(), Size3(0.22, 0.16, c.rng.uniform(0.03, 0.12)),
                             nyu40::kBooks);
                break;
            case 4:
                if (auto p = spotOn(c, s, 0.4, 0.4))
                    addBlock(c.s, child(*p, {0, 0, 0}, yaw), c.id(), Size3(0.3, 0.21, 0.012), nyu40::kPaper);
                break;
            case 5:
                if (s.headroom >= 0.5)
                    if (auto p = spotOn(c, s, 0.3, 0.3)) addTableLamp(c.s, *p, c.id());
                break;
            default:
                if (auto p = spotOn(c, s, 0.32, 0.32))
                    addPlant(c.s, *p, c.id(), std::min(s.headroom, c.rng.uniform(0.3, 0.45)));
                break;
        }
    }
}

void furnish(Ctx& c)
{
    const double area = c.area();
    const double big = std::max(1.0, area / 25.0);
    switch (c.type)
    {
        case RoomType::Living:
            addDoorsAndWindows(c, 1, 1 + c.rng.below(2));
            addSofaGroup(c);
            addTvStand(c);
            addStorage(c, c.count(1.0 * big, 2.0 * big));
            {
                const int d_poles = c.count(0.0, 0.6);
                const int d_bags = c.count(0.0, 1.0);
                const int d_floor_lamps = 1;
                const int d_plants = c.count(0.5, 1.5);
                addDecor(c, d_plants, d_floor_lamps, d_bags, d_poles);
            }
            addPictures(c, c.count(1.0, 3.0));
            addSmallObjects(c, c.count(2.0 * big, 8.0 * big));
            break;
        case RoomType::Office:
            addDoorsAndWindows(c, 1, 1 + c.rng.below(2));
            if (area > 30)  // meeting table first
                addDiningGroup(c, {0, 0}, c.L.room.sizes().x() > c.L.room.sizes().y() ? M_PI_2 : 0.0, false);
            addDesks(c, c.count(2.0 * big, 2.0 * big));
            addStorage(c, c.count(1.5 * big, 2.0 * big));
            {
                const int d_poles = c.count(0.3, 0.8);
                const int d_bags = c.count(0.0, 1.5);
                const int d_floor_lamps = c.count(0.0, 1.0);
                const int d_plants = c.count(0.5, 1.5);
                addDecor(c, d_plants, d_floor_lamps, d_bags, d_poles);
            }
            addPictures(c, c.count(1.0, 2.0));
            addSmallObjects(c, c.count(3.0 * big, 10.0 * big));
            break;
        case RoomType::Bedroom:
            addDoorsAndWindows(c, 1, 1 + c.rng.below(2));
            addBedGroup(c);
            addStorage(c, c.count(1.0 * big, 2.0 * big));
            if (c.rng.chance(0.3 + 0.5 * c.clutter)) addDesks(c, 1);
            {
                const int d_poles = 0;
                const int d_bags = c.count(0.5, 1.5);
                const int d_floor_lamps = c.count(0.0, 0.8);
                const int d_plants = c.count(0.3, 1.0);
                addDecor(c, d_plants, d_floor_lamps, d_bags, d_poles);
            }
            addPictures(c, c.count(1.0, 2.0));
            addSmallObjects(c, c.count(2.0 * big, 6.0 * big));
            break;
        case RoomType::Dining:
            addDoorsAndWindows(c, 1, 1 + c.rng.below(2));
            addDiningGroup(c, {c.rng.uniform(-0.2, 0.2), c.rng.uniform(-0.2, 0.2)},
                           c.L.room.sizes().x() > c.L.room.sizes().y() ? M_PI_2 : 0.0, true);
            addKitchenRun(c);
            addStorage(c, c.count(0.5 * big, 1.5 * big));
            {
                const int d_poles = c.count(0.0, 0.6);
                const int d_bags = c.count(0.0, 1.0);
                const int d_floor_lamps = c.count(0.0, 1.0);
                const int d_plants = c.count(0.5, 1.5);
                addDecor(c, d_plants, d_floor_lamps, d_bags, d_poles);
            }
            addPictures(c, c.count(1.0, 2.0));
            addSmallObjects(c, c.count(3.0 * big, 8.0 * big));
            break;
        case RoomType::Hall:
        {
            addDoorsAndWindows(c, 2, 2 + c.rng.below(2));
            const Eigen::Vector3d e = 0.5 * c.L.room.sizes();
            // Pillars first, on the long axis, so groups arrange around them.
            for (double side : {1.0, -1.0})
            {
                const Placement pp{Eigen::Vector3d(side * 0.12 * e.x(), side * 0.45 * e.y(), 0), 0};
                const Size3 ps(0.35, 0.35, 2 * e.z());
                if (tryAt(c, pp, ps, 0.0)) addPillar(c.s, pp, c.id(), ps.x(), ps.z());
            }
            for (double side : {-1.0, 1.0})
                addDiningGroup(c, {side * c.rng.uniform(0.3, 0.55) * e.x(), c.rng.uniform(-0.4, 0.4) * e.y()},
                               side > 0 ? 0.0 : M_PI_2, true);
            addSofaGroup(c);
            addDesks(c, c.count(1.0, 2.0));
            addKitchenRun(c);
            addStorage(c, c.count(2.0, 4.0));
            {
                const int d_poles = c.count(1.0, 1.0);
                const int d_bags = c.count(0.5, 1.5);
                const int d_floor_lamps = c.count(1.0, 1.0);
                const int d_plants = c.count(1.0, 2.0);
                addDecor(c, d_plants, d_floor_lamps, d_bags, d_poles);
            }
            addPictures(c, c.count(2.0, 3.0));
            addSmallObjects(c, c.count(6.0, 14.0));
            break;
        }
    }
}

}  // namespace

const char* toString(RoomType type)
{
    switch (type)
    {
        case RoomType::Living:
            return "living";
        case RoomType::Office:
            return "office";
        case RoomType::Bedroom:
            return "bedroom";
        case RoomType::Dining:
            return "dining";
        case RoomType::Hall:
            return "hall";
    }
    return "unknown";
}

Scene makeIndoorScene(const IndoorSceneOptions& o)
{
    const Eigen::Vector3d& sz = o.room_size;
    if (!(sz.x() >= 3.0 && sz.y() >= 3.0 && sz.z() >= 2.2) || !(sz.x() <= 30 && sz.y() <= 30 && sz.z() <= 10))
        throw InputError("makeIndoorScene: room size must be within 3 x 3 x 2.2 .. 30 x 30 x 10 m");
    if (!(o.clutter >= 0.0 && o.clutter <= 1.0)) throw InputError("makeIndoorScene: clutter must be in [0, 1]");
    Scene s;
    s.name = o.name.empty() ? std::string(toString(o.type)) + "_" + std::to_string(o.seed) : o.name;
    s.room =
        Box3(Eigen::Vector3d(-0.5 * sz.x(), -0.5 * sz.y(), 0.0), Eigen::Vector3d(0.5 * sz.x(), 0.5 * sz.y(), sz.z()));
    Ctx c{s, Layout{s.room, {}}, SimRng(o.seed, static_cast<uint64_t>(o.type) + 1), o.clutter, o.type, 1, {}, {}};
    furnish(c);
    return s;
}

namespace
{
struct ScenePreset
{
    const char* name;
    RoomType type;
    double x, y, z;  ///< room size (m)
    double clutter;
    uint64_t seed;
};
// held_*: rooms for the reported tables (doc/results.md), like living, office and bedroom,
// furnished from seeds no tuning or development run has used (the generator's own tests build
// every preset's room, these too, but map none).
constexpr ScenePreset kScenePresets[] = {
    {"small", RoomType::Living, 4.5, 4.0, 2.6, 0.3, 11},
    {"living", RoomType::Living, 6.0, 5.0, 2.7, 0.6, 21},
    {"office", RoomType::Office, 7.0, 5.5, 2.8, 0.8, 31},
    {"bedroom", RoomType::Bedroom, 4.8, 4.2, 2.6, 0.5, 41},
    {"dining", RoomType::Dining, 6.5, 5.0, 2.7, 0.6, 51},
    {"hall", RoomType::Hall, 11.0, 8.0, 3.2, 0.8, 61},
    {"held_living", RoomType::Living, 5.8, 4.8, 2.7, 0.6, 121},
    {"held_office", RoomType::Office, 6.8, 5.4, 2.8, 0.7, 131},
    {"held_bedroom", RoomType::Bedroom, 5.0, 4.4, 2.6, 0.5, 141},
};
}  // namespace

std::vector<std::string> indoorScenePresetNames()
{
    std::vector<std::string> names;
    for (const ScenePreset& p : kScenePresets) names.emplace_back(p.name);
    return names;
}

IndoorSceneOptions indoorScenePreset(const std::string& name)
{
    for (const ScenePreset& p : kScenePresets)
        if (name == p.name)
        {
            IndoorSceneOptions o;
            o.name = name;
            o.type = p.type;
            o.room_size = {p.x, p.y, p.z};
            o.clutter = p.clutter;
            o.seed = p.seed;
            return o;
        }
    std::string known;
    for (const auto& n : indoorScenePresetNames()) known += (known.empty() ? "" : ", ") + n;
    throw InputError("unknown scene preset '" + name + "' (known: " + known + ", or a number)");
}

IndoorSceneOptions randomIndoorScene(uint64_t seed)
{
    SimRng r(seed, 0xABCDEFull);
    IndoorSceneOptions o;
    o.seed = seed;
    const int t = r.below(9);  // halls are rarer
    o.type = t < 2   ? RoomType::Living
             : t < 4 ? RoomType::Office
             : t < 6 ? RoomType::Bedroom
             : t < 8 ? RoomType::Dining
                     : RoomType::Hall;
    if (o.type == RoomType::Hall)
        o.room_size = {r.uniform(9.0, 12.0), r.uniform(7.0, 9.0), r.uniform(3.0, 3.5)};
    else
        o.room_size = {r.uniform(4.2, 7.0), r.uniform(3.8, 5.5), r.uniform(2.5, 2.9)};
    o.clutter = r.uniform(0.2, 0.9);
    o.name = "rand" + std::to_string(seed);
    return o;
}

}  // namespace pndt::sim
