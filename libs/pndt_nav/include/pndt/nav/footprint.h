// An object's footprint on the floor: an oriented rectangle, and distances to it.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

namespace pndt::nav
{
struct Footprint
{
    Eigen::Vector2d center = Eigen::Vector2d::Zero();
    double yaw = 0;                                       ///< of the rectangle's local x axis
    Eigen::Vector2d half_size = Eigen::Vector2d::Zero();  ///< along local x, y

    std::array<Eigen::Vector2d, 4> corners() const;
    /// Point in the rectangle's frame.
    Eigen::Vector2d toLocal(const Eigen::Vector2d& p) const;
    /// 0 inside, else the Euclidean distance to the rectangle.
    double distanceTo(const Eigen::Vector2d& p) const;
    bool contains(const Eigen::Vector2d& p, double margin = 0) const;
    /// A copy grown by `d` on every side.
    Footprint grown(double d) const;
};

/// 0 when the rectangles overlap, else the smallest distance between them.
double footprintDistance(const Footprint& a, const Footprint& b);

/// The smallest-area rectangle around `points` (orientations in 1° steps), each
/// side pushed out by `pad`. Throws std::invalid_argument for no points.
Footprint minAreaFootprint(const std::vector<Eigen::Vector2d>& points, double pad);

}  // namespace pndt::nav
