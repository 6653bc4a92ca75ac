#include "mask_footprint.h"

#include <algorithm>

namespace pndt
{
namespace
{
void clipToImage(MaskFootprint& fp, const CameraIntrinsics& K)
{
    fp.c0 = std::max(fp.c0, 0);
    fp.r0 = std::max(fp.r0, 0);
    fp.c1 = std::min(fp.c1, K.width - 1);
    fp.r1 = std::min(fp.r1, K.height - 1);
}
}  // namespace

MaskFootprint gaussianFootprint(const NdtGaussian& g, const Pose& T_cam_world, const CameraIntrinsics& K, double k2)
{
    MaskFootprint fp;
    fp.ellipse = true;
    const Eigen::Vector3d m = T_cam_world * g.mean;
    if (m.z() <= 1e-3) return fp;
    const Eigen::Matrix3d R = T_cam_world.linear();
    const Eigen::Matrix3d Sc = R * g.cov * R.transpose();
    Eigen::Matrix<double, 2, 3> J;
    J << K.fx / m.z(), 0, -K.fx * m.x() / (m.z() * m.z()), 0, K.fy / m.z(), -K.fy * m.y() / (m.z() * m.z());
    const Eigen::Matrix2d S = J * Sc * J.transpose();
    const Eigen::Matrix2d S_inv = S.inverse();
    fp.s00 = S_inv(0, 0);
    fp.s01 = S_inv(0, 1);
    fp.s11 = S_inv(1, 1);
    fp.u0 = K.fx * m.x() / m.z() + K.cx;
    fp.v0 = K.fy * m.y() / m.z() + K.cy;
    const double rx = std::sqrt(k2 * S(0, 0)), ry = std::sqrt(k2 * S(1, 1));
    fp.c0 = clampedPixel(std::ceil(fp.u0 - rx));
    fp.c1 = clampedPixel(std::floor(fp.u0 + rx));
    fp.r0 = clampedPixel(std::ceil(fp.v0 - ry));
    fp.r1 = clampedPixel(std::floor(fp.v0 + ry));
    fp.z0 = m.z();
    clipToImage(fp, K);
    return fp;
}

MaskFootprint cubeFootprint(const Eigen::Vector3d& min_corner, double size, const Pose& T_cam_world,
                            const CameraIntrinsics& K)
{
    MaskFootprint fp;
    double umin = 1e18, umax = -1e18, vmin = 1e18, vmax = -1e18;
    for (int corner = 0; corner < 8; ++corner)
    {
        const Eigen::Vector3d p = T_cam_world * (min_corner + Eigen::Vector3d((corner & 1) * size, ((corner >> 1) & 1) * size,
                                                                              ((corner >> 2) & 1) * size));
        if (p.z() <= 1e-3) return fp;
        const double u = K.fx * p.x() / p.z() + K.cx, v = K.fy * p.y() / p.z() + K.cy;
        umin = std::min(umin, u);
        umax = std::max(umax, u);
        vmin = std::min(vmin, v);
        vmax = std::max(vmax, v);
    }
    fp.c0 = clampedPixel(std::ceil(umin));
    fp.c1 = clampedPixel(std::floor(umax));
    fp.r0 = clampedPixel(std::ceil(vmin));
    fp.r1 = clampedPixel(std::floor(vmax));
    fp.z0 = (T_cam_world * (min_corner + Eigen::Vector3d::Constant(size / 2))).z();
    clipToImage(fp, K);
    return fp;
}

}  // namespace pndt
