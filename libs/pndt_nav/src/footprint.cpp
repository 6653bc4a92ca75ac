// Oriented rectangles (footprint.h).
#include <pndt/nav/footprint.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pndt::nav
{
namespace
{
Eigen::Vector2d rotate(const Eigen::Vector2d& v, double yaw)
{
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

double segmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
    const Eigen::Vector2d ab = b - a;
    const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-18), 0.0, 1.0);
    return (a + t * ab - p).norm();
}
double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

bool segmentsCross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c, const Eigen::Vector2d& d)
{
    const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a), d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
    return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0));
}
}  // namespace

std::array<Eigen::Vector2d, 4> Footprint::corners() const
{
    const Eigen::Vector2d h = half_size;
    return {center + rotate({h.x(), h.y()}, yaw), center + rotate({-h.x(), h.y()}, yaw),
            center + rotate({-h.x(), -h.y()}, yaw), center + rotate({h.x(), -h.y()}, yaw)};
}

Eigen::Vector2d Footprint::toLocal(const Eigen::Vector2d& p) const { return rotate(p - center, -yaw); }

double Footprint::distanceTo(const Eigen::Vector2d& p) const
{
    const Eigen::Vector2d l = toLocal(p);
    const double dx = std::max(0.0, std::abs(l.x()) - half_size.x());
    const double dy = std::max(0.0, std::abs(l.y()) - half_size.y());
    return std::hypot(dx, dy);
}

bool Footprint::contains(const Eigen::Vector2d& p, double margin) const
{
    const Eigen::Vector2d l = toLocal(p);
    return std::abs(l.x()) <= half_size.x() + margin && std::abs(l.y()) <= half_size.y() + margin;
}

Footprint Footprint::grown(double d) const
{
    Footprint f = *this;
    f.half_size += Eigen::Vector2d(d, d);
    return f;
}

double footprintDistance(const Footprint& a, const Footprint& b)
{
    const auto ca = a.corners(), cb = b.corners();
    // Overlap: a corner of one inside the other, or crossing edges.
    for (const auto& p : ca)
        if (b.contains(p)) return 0;
    for (const auto& p : cb)
        if (a.contains(p)) return 0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (segmentsCross(ca[i], ca[(i + 1) % 4], cb[j], cb[(j + 1) % 4])) return 0;
    double d = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 4; ++i)
        for (const auto& p : cb) d = std::min(d, segmentDistance(p, ca[i], ca[(i + 1) % 4]));
    for (int i = 0; i < 4; ++i)
        for (const auto& p : ca) d = std::min(d, segmentDistance(p, cb[i], cb[(i + 1) % 4]));
    return d;
}

Footprint minAreaFootprint(const std::vector<Eigen::Vector2d>& points, double pad)
{
    if (points.empty()) throw std::invalid_argument("minAreaFootprint: no points");
    struct Candidate
    {
        Eigen::Vector2d lo, hi;
        double area;
    };
    std::vector<Candidate> c(90);
    double min_area = std::numeric_limits<double>::infinity();
    for (int deg = 0; deg < 90; ++deg)
    {
        const double yaw = deg * M_PI / 180.0;
        Eigen::Vector2d lo(std::numeric_limits<double>::max(), std::numeric_limits<double>::max()), hi = -lo;
        for (const auto& p : points)
        {
            const Eigen::Vector2d l = rotate(p, -yaw);
            lo = lo.cwiseMin(l);
            hi = hi.cwiseMax(l);
        }
        c[size_t(deg)] = {lo, hi, (hi - lo).prod()};
        min_area = std::min(min_area, c[size_t(deg)].area);
    }
    // Near-square or round shapes have about the same area at every angle: of the
    // angles within 3 % of the smallest area, take the one nearest the axes, so a
    // chair's footprint does not turn by a noise-picked 27 degrees.
    auto offAxes = [](int deg) { return std::min(deg, 90 - deg); };
    int best_deg = -1;
    for (int deg = 0; deg < 90; ++deg)
    {
        if (c[size_t(deg)].area > 1.03 * min_area + 1e-12) continue;
        if (best_deg < 0 || offAxes(deg) < offAxes(best_deg)) best_deg = deg;
    }
    Footprint best;
    best.yaw = best_deg * M_PI / 180.0;
    best.center = rotate(0.5 * (c[size_t(best_deg)].lo + c[size_t(best_deg)].hi), best.yaw);
    best.half_size = 0.5 * (c[size_t(best_deg)].hi - c[size_t(best_deg)].lo) + Eigen::Vector2d(pad, pad);
    // The long side along local x.
    if (best.half_size.y() > best.half_size.x())
    {
        std::swap(best.half_size.x(), best.half_size.y());
        best.yaw += M_PI / 2;
    }
    return best;
}

}  // namespace pndt::nav
