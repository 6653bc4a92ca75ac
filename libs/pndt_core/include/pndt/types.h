// Plain data types shared by every PanopticNDT library: images, intrinsics, poses.
// Header-only, Eigen only, no I/O.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <stdexcept>
#include <vector>

namespace pndt
{
/// Row-major single-channel image owning its pixels.
template <typename T>
struct Image
{
    int width = 0;
    int height = 0;
    std::vector<T> data;

    Image() = default;
    Image(int w, int h, T fill = T{}) { resize(w, h, fill); }

    /// Resizes and fills; keeps the allocation when it is large enough.
    void resize(int w, int h, T fill = T{})
    {
        width = w;
        height = h;
        data.assign(static_cast<size_t>(w) * static_cast<size_t>(h), fill);
    }
    /// Resizes without filling, for outputs that write every pixel: the pixels kept
    /// hold stale values (new ones zero); keeps the allocation when it is large enough.
    void reshape(int w, int h)
    {
        width = w;
        height = h;
        data.resize(static_cast<size_t>(w) * static_cast<size_t>(h));
    }
    bool empty() const { return data.empty(); }
    size_t size() const { return data.size(); }
    T& at(int row, int col) { return data[static_cast<size_t>(row) * width + col]; }
    const T& at(int row, int col) const { return data[static_cast<size_t>(row) * width + col]; }
    bool sameSize(int w, int h) const { return width == w && height == h; }
};

/// Pinhole intrinsics in pixels. Camera frame is OpenCV's optical frame:
/// x right, y down, z forward (the depth axis).
struct CameraIntrinsics
{
    int width = 0;
    int height = 0;
    double fx = 0, fy = 0, cx = 0, cy = 0;

    bool valid() const { return invalidReason().empty(); }
    /// Empty if the intrinsics describe a camera, else what is wrong, naming the field: a
    /// positive size, finite values, positive focal lengths, and no pixel's ray more than
    /// 89.4 degrees off the optical axis (a focal length of 1e-12 made rays of 10^14 m).
    std::string invalidReason() const
    {
        const auto num = [](double v) { return std::to_string(v); };
        if (width <= 0 || height <= 0)
            return "size " + std::to_string(width) + "x" + std::to_string(height) + " is not positive";
        if (!(std::isfinite(fx) && fx > 0)) return "fx=" + num(fx) + " is not a positive number";
        if (!(std::isfinite(fy) && fy > 0)) return "fy=" + num(fy) + " is not a positive number";
        if (!std::isfinite(cx)) return "cx=" + num(cx) + " is not a number";
        if (!std::isfinite(cy)) return "cy=" + num(cy) + " is not a number";
        constexpr double kMaxSlope = 100;  // tan(89.4 deg)
        if (std::max(std::abs(cx), std::abs(width - 1 - cx)) > kMaxSlope * fx ||
            std::max(std::abs(cy), std::abs(height - 1 - cy)) > kMaxSlope * fy)
            return "fx=" + num(fx) + ", fy=" + num(fy) + " with cx=" + num(cx) + ", cy=" + num(cy) + " at " +
                   std::to_string(width) + "x" + std::to_string(height) +
                   " give pixels more than 89.4 degrees off the optical axis";
        return {};
    }

    /// Point in the camera frame for pixel (col,row) at depth z (metres, along +z).
    Eigen::Vector3d unproject(double col, double row, double z) const
    {
        return {(col - cx) * z / fx, (row - cy) * z / fy, z};
    }
    /// Pixel of a camera-frame point; false if behind the camera.
    bool project(const Eigen::Vector3d& p, double& col, double& row) const
    {
        if (p.z() <= 0) return false;
        col = fx * p.x() / p.z() + cx;
        row = fy * p.y() / p.z() + cy;
        return true;
    }
    /// Same camera model, image scaled by `s` (e.g. 0.5 for half resolution).
    CameraIntrinsics scaled(double s) const
    {
        CameraIntrinsics k = *this;
        k.width = static_cast<int>(width * s);
        k.height = static_cast<int>(height * s);
        k.fx *= s;
        k.fy *= s;
        k.cx = (cx + 0.5) * s - 0.5;
        k.cy = (cy + 0.5) * s - 0.5;
        return k;
    }
};

/// What a depth value measures: the distance along the optical axis (z: OpenNI2,
/// Kinect, RealSense, TUM, Redwood) or along the pixel's ray from the camera centre
/// (range: some time-of-flight cameras, simulators, MRPT scans with range_is_depth = false).
enum class RangeKind
{
    Z,
    Ray,
};

/// Rigid transform; `T_a_b` maps points from frame b into frame a.
using Pose = Eigen::Isometry3d;

/// Empty if T is a rigid motion (finite, its rotation orthonormal with determinant 1 within
/// 1e-3), else what is wrong: an unnormalised quaternion read from a file scales the scene.
inline std::string poseInvalidReason(const Pose& T)
{
    if (!T.matrix().array().isFinite().all()) return "the camera pose is not finite";
    const Eigen::Matrix3d R = T.linear();
    const double off = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    const double det = R.determinant();
    if (off > 1e-3 || std::abs(det - 1) > 1e-3)
        return "the camera pose's rotation is not a rotation (R^T R differs from I by up to " + std::to_string(off) +
               ", det R = " + std::to_string(det) + "; an unnormalised quaternion?)";
    return {};
}

/// Thrown for malformed input (sizes, labels, files); the message names the source.
struct InputError : std::runtime_error
{
    using std::runtime_error::runtime_error;
};

}  // namespace pndt
