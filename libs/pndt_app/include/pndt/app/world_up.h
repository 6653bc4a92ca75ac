// Which way is up in a pose world. The floor plan, the overview, pndt-nav's grid and MRPT's 2D
// tools take world z as up; worlds of datasets often are not (Redwood's is its first camera,
// y down). The poses' own up tells: a robot's z, or, for camera poses, the camera's -y (upright
// for a hand-held camera; a camera mounted on a robot is known by its mount, the sensor pose).
#pragma once

#include <mrpt/poses/CPose3D.h>
#include <pndt/types.h>

#include <optional>
#include <string>

namespace pndt::app
{
/// The up of a camera pose's own frame, in the optical frame: -y.
inline Eigen::Vector3d opticalUp() { return -Eigen::Vector3d::UnitY(); }
/// The robot's up (its z) in the optical frame of a camera mounted at `robot_to_camera` (MRPT
/// sensor axes): -y for the identity mount.
Eigen::Vector3d robotUpInCamera(const mrpt::poses::CPose3D& robot_to_camera);
/// An up direction of the pose's frame (`up_in_camera`, optical axes) in the world.
inline Eigen::Vector3d worldUp(const Pose& T_world_cam, const Eigen::Vector3d& up_in_camera = opticalUp())
{
    return T_world_cam.linear() * up_in_camera;
}
/// The world axis (+-x, +-y, +-z) nearest `v`: a dataset's world is one axis-aligned turn
/// away from z-up, and a camera's own tilt is not part of it.
Eigen::Vector3d nearestAxis(const Eigen::Vector3d& v);

/// The rotation about the world origin that takes `up` (any length > 0) to +z, the smallest
/// such (about the axis up x z).
Pose levellingRotation(const Eigen::Vector3d& up);

/// "(x, y, z)" with `decimals` decimals, without negative zeros ("-0.000").
std::string directionText(const Eigen::Vector3d& v, int decimals);

/// Angle between two directions, degrees.
double angleDegrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

/// The cameras' up directions summed over a run: whether the world looks z-up.
class CameraUpTally
{
   public:
    /// Cameras whose mean up is further than this from +z make the world "not z-up".
    static constexpr double kMaxTiltDegrees = 45.0;

    /// `up_in_camera`: the up of the pose's own frame (opticalUp(), or robotUpInCamera).
    void add(const Pose& T_world_cam, const Eigen::Vector3d& up_in_camera = opticalUp())
    {
        sum_ += worldUp(T_world_cam, up_in_camera);
        ++count_;
    }
    size_t count() const { return count_; }
    /// Mean direction of the cameras' up (unit), or zero without cameras.
    Eigen::Vector3d meanUp() const;
    /// A note when the mean up is more than kMaxTiltDegrees from +z (what it is, what takes
    /// z as up, what to do: `remedy`), else nothing.
    std::optional<std::string> notZUpNote(const std::string& remedy) const;

   private:
    Eigen::Vector3d sum_ = Eigen::Vector3d::Zero();
    size_t count_ = 0;
};

}  // namespace pndt::app
