#include <fmt/format.h>
#include <pndt/app/world_up.h>

#include <algorithm>
#include <cmath>

namespace pndt::app
{
Pose levellingRotation(const Eigen::Vector3d& up)
{
    Pose R = Pose::Identity();
    R.linear() = Eigen::Quaterniond::FromTwoVectors(up.normalized(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return R;
}

std::string directionText(const Eigen::Vector3d& v, int decimals)
{
    const double half_unit = 0.5 * std::pow(10.0, -decimals);
    const auto tidy = [&](double x) { return std::abs(x) < half_unit ? 0.0 : x; };
    return fmt::format("({:.{}f}, {:.{}f}, {:.{}f})", tidy(v.x()), decimals, tidy(v.y()), decimals, tidy(v.z()),
                       decimals);
}

double angleDegrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
    const double c = a.normalized().dot(b.normalized());
    return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
}

Eigen::Vector3d CameraUpTally::meanUp() const
{
    return count_ == 0 || sum_.norm() < 1e-12 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(sum_.normalized());
}

std::optional<std::string> CameraUpTally::notZUpNote(const std::string& remedy) const
{
    const Eigen::Vector3d up = meanUp();
    if (up.isZero()) return std::nullopt;
    const double tilt = angleDegrees(up, Eigen::Vector3d::UnitZ());
    if (tilt <= kMaxTiltDegrees) return std::nullopt;
    return fmt::format("the cameras' up points along world {} on average, {:.0f} degrees from +z: the floor plan, "
                       "the overview, pndt-nav's grid and MRPT's 2D tools take world z as up{}",
                       directionText(up, 2), tilt, remedy.empty() ? "" : " (" + remedy + ")");
}

}  // namespace pndt::app
