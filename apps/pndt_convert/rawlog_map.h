// Reads a converted rawlog back and maps it (geometry, and labels when present) into a
// pndt::PanopticNDTMap, the way a consumer of design §5 rawlogs does; plus PNG views of the result.
// Used by pndt-rawlog-preview and by the converter's end-to-end tests.
#pragma once

#include <opencv2/core.hpp>
#include <pndt/mrpt/PanopticNDTMap.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace pndt::convert
{
struct RawlogMapOptions
{
    /// A scan takes the robot pose at its stamp, interpolated (SLERP, MRPT's CPose3DInterpolator)
    /// between the file's two CObservationRobotPoses around it, wherever they stand in the file,
    /// if the one after it is at most this far (seconds; the interpolator's maxTimeInterpolation);
    /// otherwise the scan is skipped and counted (never mapped with a stale pose). Converted
    /// rawlogs hold a pose at each scan's stamp; pndt-live's recordings hold the localiser's
    /// poses in the order they arrived.
    double pose_max_gap = 0.1;
    size_t max_scans = 0;  ///< 0 = all
};

struct RawlogMapResult
{
    size_t objects = 0;
    size_t scans = 0;
    size_t scans_mapped = 0;
    size_t scans_without_pose = 0;
    size_t robot_poses = 0;
    size_t label_images = 0;
    size_t other_objects = 0;
    double seconds_read = 0;  ///< decompressing and deserialising
    double seconds_map = 0;   ///< insertObservation calls
    std::vector<Pose> cameras;        ///< optical camera pose of every mapped scan
    PanopticFrame first_frame;        ///< depth + intrinsics of the first mapped scan
};

/// Maps every scan of `path` with the robot pose at its stamp (scan.sensorPose applied by the
/// map): a first pass reads the robot poses, a second maps.
/// `progress(scans_seen)` is called after each scan. Reads either rawlog format (observations or
/// sensory frames) through pndt::app::ObservationStream. Throws std::runtime_error naming the file
/// if it cannot be opened, or, with the object number and byte, if it is truncated or corrupt.
RawlogMapResult mapRawlog(const std::string& path, PanopticNDTMap& map, const RawlogMapOptions& options = {},
                          const std::function<void(size_t)>& progress = {});

/// Colour image (BGR) of a depth image: turbo colour map over [dmin, dmax] metres, black = invalid.
cv::Mat colorizeDepth(const Image<float>& depth, double dmin, double dmax);

/// The map rendered from `T_world_cam`, each pixel coloured by the height of its surface point along
/// `up` (turbo over [hmin, hmax] metres) and darkened with distance for depth cues; black = nothing.
cv::Mat renderHeightView(const PanopticMap& map, const Pose& T_world_cam, const CameraIntrinsics& K,
                         const Eigen::Vector3d& up, double hmin, double hmax);

/// The camera a viewer would choose for an overview: looking down at `elevation_deg` onto the
/// robust (2–98 %) bounding box of the occupied voxels, from the side the cameras mostly look
/// from, far enough for the box to fit into K's field of view. `up` = world up direction.
Pose overviewCamera(const PanopticMap& map, const std::vector<Pose>& cameras, const Eigen::Vector3d& up,
                    const CameraIntrinsics& K, double elevation_deg = 50.0);

/// Robust height range (2–98 %) of the occupied voxel centres along `up`.
std::pair<double, double> heightRange(const PanopticMap& map, const Eigen::Vector3d& up);

/// Measured vs rendered depth over the pixels with a valid measurement.
struct DepthAgreement
{
    size_t measured = 0;  ///< pixels with valid measured depth
    size_t rendered = 0;  ///< ... of which the render has a surface
    size_t agree = 0;     ///< ... of which |rendered - measured| <= abs_tol + rel_tol * measured
    double median_abs_error = 0;  ///< over the `rendered` pixels, metres
    double agreeFraction() const { return measured ? double(agree) / double(measured) : 0.0; }
    double coverage() const { return measured ? double(rendered) / double(measured) : 0.0; }
};
DepthAgreement compareDepth(const Image<float>& measured, const Image<float>& rendered, double abs_tol,
                            double rel_tol);

/// Writes a PNG atomically; throws std::runtime_error naming the file on failure.
void writePng(const cv::Mat& image, const std::string& path);

}  // namespace pndt::convert
