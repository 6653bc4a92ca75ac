// A camera pose from where it is and what it looks at (optical convention:
// x right, y down, z forward). Header-only, like pndt/types.h: the synthetic
// scenes (pndt_sim) build without pndt_core.
#pragma once

#include <Eigen/Geometry>

#include "pndt/types.h"

namespace pndt
{
/// T_world_cam of a camera at `eye` whose optical z axis points at `target`, with its
/// x axis perpendicular to `up` (horizontal for up = world z) and its y axis pointing
/// "down" (y . up < 0). Throws InputError if eye == target or the view is parallel to up.
inline Pose lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                   const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ())
{
    const Eigen::Vector3d view = target - eye;
    const double len = view.norm();
    if (!(len > 0)) throw InputError("lookAt: eye and target coincide");
    const Eigen::Vector3d z = view / len;
    Eigen::Vector3d x = z.cross(up);
    const double xn = x.norm();
    if (!(xn > 1e-12 * up.norm()) || !(up.norm() > 0))
        throw InputError("lookAt: viewing direction parallel to the up vector");
    x /= xn;
    const Eigen::Vector3d y = z.cross(x);
    Pose T = Pose::Identity();
    T.linear().col(0) = x;
    T.linear().col(1) = y;
    T.linear().col(2) = z;
    T.translation() = eye;
    return T;
}

}  // namespace pndt
