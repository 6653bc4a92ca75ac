// Which way is up in a pose world. The floor plan, the overview, pndt-nav's grid and MRPT's 2D
// tools take world z as up; worlds of datasets often are not (Redwood's is its first camera,
// y down). The cameras' own up (-y of the optical frame, upright for a hand-held or robot
// camera) tells, and gives the rotation that levels such a world.
#pragma once

#include <pndt/types.h>

#include <optional>
#include <string>

namespace pndt::app
{
/// A camera's up in the world: -y of its optical frame.
inline Eigen::Vector3d cameraUp(const Pose& T_world_cam) { return -T_world_cam.linear().col(1); }

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

    void add(const Pose& T_world_cam)
    {
        sum_ += cameraUp(T_world_cam);
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
