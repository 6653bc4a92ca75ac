// Pose-file readers: TUM, RTAB-Map exports (ids 0, 1, 2, 4, 10, 11), KITTI, Redwood/Open3D `.log`
// and the nicr-scene-analysis-datasets per-frame extrinsics JSON.
//
// Frame conventions (read this before using a pose):
//  * `optical` = OpenCV camera frame: x right, y down, z forward (the depth axis). This is the frame
//    of pndt::CameraIntrinsics::unproject(), so a pose T_world_optical maps unprojected points into
//    the world.
//  * `body` = ROS REP-103 base/robot frame: x forward, y left, z up. MRPT uses the same axes for
//    robots and for the depth-sensor frame of CObservation3DRangeScan.
//  * Every returned pose is `T_world_sensor` (maps sensor-frame points into the world frame). What
//    "world" and "sensor" are depends on the format; each PoseFormat value below says it.
//
// Errors: every malformed input throws pndt::InputError whose message names the file and, for text
// formats, the 1-based line number and the problem ("poses.txt (line 7): expected 8 numbers ...").
// Poses with non-finite numbers (nan/inf; ScanNet has some) are by default NOT an error: they are
// skipped, counted in PoseReadReport and their position in the file still advances the implicit
// index (so "frame i <-> i-th pose" stays aligned for stampless formats). Set
// PoseReadOptions::non_finite_is_error to throw instead. Non-finite *timestamps* always throw.
// Quaternions must have norm within 1e-2 of 1 (then they are normalised); zero / far-from-unit
// quaternions throw. Rotation matrices must satisfy max|RᵀR − I| ≤ 1e-3 and det > 0 (then they are
// re-orthonormalised); anything else throws.
#pragma once

#include <pndt/types.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pndt::io
{
/// One pose sample. `T_world_sensor` maps points of the sensor frame into the world frame.
struct StampedPose
{
    double t = 0;  ///< seconds (or a synthetic stamp for stampless formats, see PoseFormat)
    Pose T_world_sensor = Pose::Identity();
    int64_t id = -1;  ///< id from the file when the format has one (RTAB-Map 11, g2o, .log, nicr), else -1
};

/// Supported pose-file formats and what the returned pose means.
enum class PoseFormat
{
    /// TUM RGB-D `t tx ty tz qx qy qz qw` (comments '#'). Pose of the colour camera's optical frame
    /// in the motion-capture world: T_world_optical. Returned as stored.
    Tum,
    /// RTAB-Map "Raw" (id 0): 12 numbers r11 r12 r13 tx r21 .. tz (3x4 row-major), no stamp.
    /// t = 0-based index of the pose line (non-finite lines still consume an index).
    /// Returned as stored = RTAB-Map's internal pose: world = RTAB-Map map frame (ROS axes, z up),
    /// sensor = the exported frame (`rtabmap-export --poses`: body/base_link; `--poses_camera`:
    /// the camera optical frame, since RTAB-Map's camera localTransform includes the optical
    /// rotation).
    Rtabmap0,
    /// RTAB-Map "RGBD-SLAM motion capture" (id 1): `stamp x y z qx qy qz qw`. RTAB-Map writes
    /// P = R_ob · A · T · R_bo with A = [[0,0,1],[0,-1,0],[1,0,0]] (its mocap world) and
    /// R_bo = bodyFromOptical().rotation(). We undo this exactly as rtabmap::graph::importPoses
    /// does: T = A · R_bo · P · R_ob, so the result is RTAB-Map's internal pose (same meaning as
    /// Rtabmap0). Use PoseFormat::Tum to get the file's numbers unconverted.
    Rtabmap1,
    /// RTAB-Map "KITTI" (id 2): 12 numbers like Raw but written in optical axes,
    /// P = R_ob · T · R_bo. We return T = R_bo · P · R_ob (RTAB-Map's internal pose, as Rtabmap0).
    /// t = line index. For a KITTI-benchmark poses file use PoseFormat::Kitti instead.
    Rtabmap2,
    /// RTAB-Map g2o export (id 4): `VERTEX_SE3:QUAT id x y z qx qy qz qw` lines (VERTEX_SE2
    /// `id x y theta` is accepted as planar). EDGE_*, VERTEX_TRACKXYZ/XY (landmarks),
    /// VERTEX_SWITCH, PARAMS_*, FIX lines are ignored. t = id = vertex id. Pose meaning as Rtabmap0.
    Rtabmap4,
    /// RTAB-Map "RGBD-SLAM in ROS frame" (id 10): `stamp x y z qx qy qz qw`, no conversion
    /// (as Rtabmap0, with stamps).
    Rtabmap10,
    /// RTAB-Map id 11: as 10 plus a trailing integer node id (stored in StampedPose::id).
    Rtabmap11,
    /// KITTI odometry poses file: 12 numbers per line (3x4 row-major) = T_cam0_camI in optical
    /// axes, returned as stored; t = line index.
    Kitti,
    /// Redwood / Open3D `.log`: blocks of a header line `id id n` followed by the 4 rows of the
    /// 4x4 camera-to-world matrix: T_world_optical (Open3D's pinhole camera = optical axes).
    /// t = block index / frame_rate_hz; id = first header number.
    Redwood,
    /// nicr-scene-analysis-datasets extrinsics JSON `{x,y,z,quat_x,quat_y,quat_z,quat_w}`,
    /// camera-to-world in optical axes (ScanNet: frame.camera_to_world; Hypersim: rotated by 180°
    /// about x in the dataset preparation so that it is OpenCV-style). `path` may be one file
    /// (t = 0) or a folder of `<frame>.json` files (sorted by name; id = numeric stem,
    /// t = id / frame_rate_hz). Python's json writes non-finite values as NaN/Infinity tokens;
    /// they are accepted and treated as non-finite (skipped and counted by default).
    Nicr,
};

struct PoseReadOptions
{
    /// true: a pose with nan/inf values throws; false (default): it is skipped and counted.
    bool non_finite_is_error = false;
    /// Synthetic stamp for stampless formats with a natural frame rate (Redwood, nicr folders).
    double frame_rate_hz = 30.0;
};

/// What a reader skipped (only non-finite poses are ever skipped).
struct PoseReadReport
{
    size_t skipped_non_finite = 0;
    std::vector<std::string> skipped_where;  ///< "file (line N)" or file name, one per skip
};

/// "tum", "rtabmap0".."rtabmap11" (also "raw"=0, "g2o"=4, "kitti", "redwood" or "log", "nicr");
/// case-insensitive. Throws InputError naming the unknown value and listing the accepted ones.
PoseFormat parsePoseFormat(const std::string& name);
/// Canonical name accepted by parsePoseFormat().
std::string toString(PoseFormat format);
/// True for the formats whose poses carry no stamp (rtabmap0/2/4, kitti, redwood): their t is
/// made up from the index (index / frame_rate_hz), so they match frames by index, not by time.
bool isStampless(PoseFormat format);

/// Reads any supported format (dispatches to the functions below).
std::vector<StampedPose> readPoseFile(const std::string& path, PoseFormat format,
                                      const PoseReadOptions& options = {},
                                      PoseReadReport* report = nullptr);

std::vector<StampedPose> readTumPoses(const std::string& path, const PoseReadOptions& options = {},
                                      PoseReadReport* report = nullptr);
/// `format` is the RTAB-Map id: 0, 1, 2, 4, 10 or 11 (anything else throws).
std::vector<StampedPose> readRtabmapPoses(const std::string& path, int format,
                                          const PoseReadOptions& options = {},
                                          PoseReadReport* report = nullptr);
std::vector<StampedPose> readKittiPoses(const std::string& path,
                                        const PoseReadOptions& options = {},
                                        PoseReadReport* report = nullptr);
std::vector<StampedPose> readRedwoodLog(const std::string& path,
                                        const PoseReadOptions& options = {},
                                        PoseReadReport* report = nullptr);
/// File or folder, see PoseFormat::Nicr.
std::vector<StampedPose> readNicrPoses(const std::string& path,
                                       const PoseReadOptions& options = {},
                                       PoseReadReport* report = nullptr);

/// One nicr extrinsics JSON: T_world_optical, or std::nullopt when it holds non-finite values.
/// Throws on malformed JSON, missing keys, non-numeric values or a bad quaternion.
std::optional<Pose> readNicrExtrinsicsJson(const std::string& path);

/// T_body_optical of a camera whose optical frame sits at the body origin: maps optical
/// coordinates (x right, y down, z fwd) to body coordinates (x fwd, y left, z up). Rotation rows
/// [[0,0,1],[-1,0,0],[0,-1,0]]; equals MRPT's CPose3D(0,0,0,-90°,0,-90°), the default
/// CObservation3DRangeScan::relativePoseIntensityWRTDepth. So a MRPT depth-sensor pose is
/// T_world_mrptsensor = T_world_optical · opticalFromBody().
Pose bodyFromOptical();
/// Inverse of bodyFromOptical().
Pose opticalFromBody();

}  // namespace pndt::io
