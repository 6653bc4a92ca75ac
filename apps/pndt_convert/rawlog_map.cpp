#include "rawlog_map.h"

#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/poses/CPose3DInterpolator.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <pndt/app/map_pictures.h>
#include <pndt/app/observation_stream.h>
#include <pndt/look_at.h>
#include <pndt/mrpt/map_files.h>
#include <pndt/mrpt/observation_frame.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>

namespace pndt::convert
{
namespace
{
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// Value at quantile q of v (v is reordered).
double quantile(std::vector<double>& v, double q)
{
    if (v.empty()) return 0;
    const size_t k = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + long(k), v.end());
    return v[k];
}

cv::Vec3b turbo(double x)
{
    static const cv::Mat lut = [] {
        cv::Mat ramp(1, 256, CV_8UC1);
        for (int i = 0; i < 256; ++i) ramp.at<uint8_t>(0, i) = uint8_t(i);
        cv::Mat out;
        cv::applyColorMap(ramp, out, cv::COLORMAP_TURBO);
        return out;
    }();
    const int i = std::clamp(int(std::lround(std::clamp(x, 0.0, 1.0) * 255.0)), 0, 255);
    return lut.at<cv::Vec3b>(0, i);
}
}  // namespace

RawlogMapResult mapRawlog(const std::string& path, PanopticNDTMap& map, const RawlogMapOptions& o,
                          const std::function<void(size_t)>& progress)
{
    RawlogMapResult res;
    // Pass 1: the robot poses by stamp, wherever they stand (a live recording has them in the
    // order they arrived: all first, or after their frames).
    mrpt::poses::CPose3DInterpolator poses;
    poses.setInterpolationMethod(mrpt::poses::imLinearSlerp);
    poses.setMaxTimeInterpolation(std::chrono::duration_cast<mrpt::Clock::duration>(
        std::chrono::duration<double>(o.pose_max_gap)));
    {
        const auto t_read = Clock::now();
        app::ObservationStream in(path);
        while (const mrpt::obs::CObservation::Ptr obj = in.next())
            if (auto pose = std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(obj))
            {
                poses.insert(pose->timestamp, pose->pose.mean);
                ++res.robot_poses;
            }
        if (in.truncated()) throw std::runtime_error(in.stopReason());
        res.seconds_read += since(t_read);
    }
    const auto poseAt = [&](mrpt::Clock::time_point t) -> std::optional<mrpt::poses::CPose3D> {
        mrpt::poses::CPose3D p;
        bool valid = false;
        poses.interpolate(t, p, valid);
        if (!valid) return std::nullopt;
        return p;
    };
    // Pass 2: mapping.
    app::ObservationStream in(path);  // either rawlog format; says where a damaged file stops
    for (;;)
    {
        if (o.max_scans && res.scans >= o.max_scans) break;
        const auto t_read = Clock::now();
        const mrpt::obs::CObservation::Ptr obj = in.next();
        res.seconds_read += since(t_read);
        if (!obj) break;

        if (std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(obj))
            continue;  // read in the first pass
        else if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(obj))
        {
            ++res.scans;
            const std::optional<mrpt::poses::CPose3D> pose = poseAt(scan->timestamp);
            if (!pose)
                ++res.scans_without_pose;
            else
            {
                const mrpt::poses::CPose3D robot = *pose;
                if (res.scans_mapped == 0) depthFrameFrom(*scan, res.first_frame);
                const auto t_map = Clock::now();
                map.insertObservation(*scan, robot);
                res.seconds_map += since(t_map);
                res.cameras.push_back(cameraPoseInWorld(robot, scan->sensorPose));
                ++res.scans_mapped;
            }
            if (progress) progress(res.scans);
        }
        else if (auto img = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(obj))
        {
            ++res.label_images;
            // Paired with their scan by stamp, mapped at the scan's pose: the pose here is unused.
            const auto t_map = Clock::now();
            map.insertObservation(*img, mrpt::poses::CPose3D());
            res.seconds_map += since(t_map);
        }
        else
            ++res.other_objects;
    }
    res.objects = in.objectsRead();
    if (in.truncated()) throw std::runtime_error(in.stopReason());
    const auto t_map = Clock::now();
    map.flushPending();
    res.seconds_map += since(t_map);
    return res;
}

cv::Mat colorizeDepth(const Image<float>& depth, double dmin, double dmax)
{
    cv::Mat img(depth.height, depth.width, CV_8UC3, cv::Scalar(0, 0, 0));
    const double span = std::max(1e-9, dmax - dmin);
    for (int r = 0; r < depth.height; ++r)
        for (int c = 0; c < depth.width; ++c)
        {
            const float d = depth.at(r, c);
            if (d > 0 && std::isfinite(d)) img.at<cv::Vec3b>(r, c) = turbo((d - dmin) / span);
        }
    return img;
}

cv::Mat renderHeightView(const PanopticMap& map, const Pose& T, const CameraIntrinsics& K, const Eigen::Vector3d& up,
                         double hmin, double hmax)
{
    RenderedView v;
    map.render(T, K, v);
    std::vector<double> depths;
    for (float d : v.depth.data)
        if (d > 0 && std::isfinite(d)) depths.push_back(d);
    const double dnear = quantile(depths, 0.02), dfar = quantile(depths, 0.98);
    cv::Mat img(K.height, K.width, CV_8UC3, cv::Scalar(0, 0, 0));
    const double span = std::max(1e-9, hmax - hmin);
    for (int r = 0; r < K.height; ++r)
        for (int c = 0; c < K.width; ++c)
        {
            const float d = v.depth.at(r, c);
            if (!(d > 0 && std::isfinite(d))) continue;
            const Eigen::Vector3d p = T * K.unproject(c, r, d);
            cv::Vec3b col = turbo((p.dot(up) - hmin) / span);
            // Farther surfaces a little darker (depth cue), never below 55 %.
            const double shade = 1.0 - 0.45 * std::clamp((d - dnear) / std::max(1e-9, dfar - dnear), 0.0, 1.0);
            for (int k = 0; k < 3; ++k) col[k] = uint8_t(std::lround(col[k] * shade));
            img.at<cv::Vec3b>(r, c) = col;
        }
    return img;
}

std::pair<double, double> heightRange(const PanopticMap& map, const Eigen::Vector3d& up)
{
    std::vector<double> h;
    const VoxelStore& s = map.voxels();
    for (uint32_t i = 0; i < s.size(); ++i)
        if (map.isOccupied(s[i])) h.push_back(map.grid().center(s.key(i)).dot(up));
    if (h.empty()) return {0.0, 1.0};
    const double lo = quantile(h, 0.02), hi = quantile(h, 0.98);
    return {lo, std::max(hi, lo + 1e-3)};
}

Pose overviewCamera(const PanopticMap& map, const std::vector<Pose>& cameras, const Eigen::Vector3d& up_in,
                    const CameraIntrinsics& K, double elevation_deg)
{
    const Eigen::Vector3d up = up_in.normalized();
    std::vector<double> xs, ys, zs;
    const VoxelStore& s = map.voxels();
    for (uint32_t i = 0; i < s.size(); ++i)
        if (map.isOccupied(s[i]))
        {
            const Eigen::Vector3d c = map.grid().center(s.key(i));
            xs.push_back(c.x());
            ys.push_back(c.y());
            zs.push_back(c.z());
        }
    if (xs.empty()) throw std::runtime_error("overviewCamera: the map has no occupied voxel");
    Eigen::Vector3d lo, hi;
    lo << quantile(xs, 0.02), quantile(ys, 0.02), quantile(zs, 0.02);
    hi << quantile(xs, 0.98), quantile(ys, 0.98), quantile(zs, 0.98);
    const Eigen::Vector3d centre = 0.5 * (lo + hi);
    const double radius = std::max(0.5, 0.5 * (hi - lo).norm());

    // Horizontal viewing direction: the cameras' mean forward direction, projected on the floor.
    Eigen::Vector3d fwd = Eigen::Vector3d::Zero();
    for (const Pose& c : cameras) fwd += c.linear().col(2);
    fwd -= fwd.dot(up) * up;
    if (fwd.norm() < 1e-6) fwd = up.unitOrthogonal();
    fwd.normalize();

    const double half_fov = std::atan(0.5 * std::min(K.width / K.fx, K.height / K.fy));
    const double dist = 0.85 * radius / std::sin(half_fov);
    const double el = elevation_deg * M_PI / 180.0;
    const Eigen::Vector3d eye = centre - fwd * dist * std::cos(el) + up * dist * std::sin(el);
    // Looking straight down (elevation 90 degrees), the image's "up" is the forward direction.
    const bool straight_down = (centre - eye).normalized().cross(up).norm() < 1e-9;
    return lookAt(eye, centre, straight_down ? fwd : up);
}

DepthAgreement compareDepth(const Image<float>& measured, const Image<float>& rendered, double abs_tol,
                            double rel_tol)
{
    if (!measured.sameSize(rendered.width, rendered.height))
        throw std::invalid_argument("compareDepth: images differ in size");
    DepthAgreement a;
    std::vector<double> err;
    for (size_t i = 0; i < measured.data.size(); ++i)
    {
        const float m = measured.data[i], r = rendered.data[i];
        if (!(m > 0 && std::isfinite(m))) continue;
        ++a.measured;
        if (!(r > 0 && std::isfinite(r))) continue;
        ++a.rendered;
        const double e = std::abs(double(r) - double(m));
        err.push_back(e);
        if (e <= abs_tol + rel_tol * m) ++a.agree;
    }
    a.median_abs_error = quantile(err, 0.5);
    return a;
}

void writePng(const cv::Mat& image, const std::string& path) { app::writePngFile(image, path); }

}  // namespace pndt::convert
