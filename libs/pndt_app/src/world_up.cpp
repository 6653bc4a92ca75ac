#include <fmt/format.h>
#include <pndt/app/world_up.h>
#include <pndt/mrpt/observation_frame.h>

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

Eigen::Vector3d robotUpInCamera(const mrpt::poses::CPose3D& robot_to_camera)
{
    const Pose T_robot_cam = cameraPoseInWorld(mrpt::poses::CPose3D(), robot_to_camera);
    return T_robot_cam.linear().transpose() * Eigen::Vector3d::UnitZ();
}

Eigen::Vector3d nearestAxis(const Eigen::Vector3d& v)
{
    Eigen::Vector3d::Index i = 0;
    v.cwiseAbs().maxCoeff(&i);
    Eigen::Vector3d a = Eigen::Vector3d::Zero();
    a[i] = v[i] < 0 ? -1.0 : 1.0;
    return a;
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
    return fmt::format("the poses' up (a robot's z, a camera's -y) points along world {} on average, {:.0f} degrees "
                       "from +z: the floor plan, "
                       "the overview, pndt-nav's grid and MRPT's 2D tools take world z as up{}",
                       directionText(up, 2), tilt, remedy.empty() ? "" : " (" + remedy + ")");
}

}  // namespace pndt::app
