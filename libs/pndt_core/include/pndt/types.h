// Plain data types shared by every PanopticNDT library: images, intrinsics, poses.
// Header-only, Eigen only, no I/O.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
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

    bool valid() const { return width > 0 && height > 0 && fx > 0 && fy > 0; }

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

/// Thrown for malformed input (sizes, labels, files); the message names the source.
struct InputError : std::runtime_error
{
    using std::runtime_error::runtime_error;
};

}  // namespace pndt
