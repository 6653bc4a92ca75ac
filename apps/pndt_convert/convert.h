// pndt-convert: RGB-D sequence folders (Redwood/Open3D, TUM RGB-D, nicr-scene-analysis-datasets
// incl. EMSANet .npz predictions) → MRPT rawlog in the design §5 shape, written by
// pndt::RawlogFrameWriter: per frame a CObservationRobotPose, the CObservation3DRangeScan and,
// when the frame has labels, the two float32 panoptic CObservationImages.
//
// Every frame written has a pose: frames without one (none in the source, outside the pose
// file, a gap larger than max_pose_gap, a non-finite pose) are skipped and counted, never given
// a stale pose. Malformed input throws pndt::InputError naming the file (and line, for text
// formats); nothing appears at the output path unless the conversion succeeds.
#pragma once

#include <mrpt/poses/CPose3D.h>
#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pndt::convert
{
struct ConvertOptions
{
    std::string input;   ///< sequence folder (nicr: the split folder, e.g. <dataset>/valid)
    std::string output;  ///< rawlog path (parent folders are created)
    /// "auto", "redwood", "tum" or "nicr". auto: nicr if the folder has depth_intrinsics/ or a
    /// sequence is given; tum if it has rgb.txt + depth.txt or an association file with stamps;
    /// redwood if it has depth/.
    std::string format = "auto";

    // --- nicr-scene-analysis-datasets
    std::string sequence;         ///< <seq> below depth/; empty = the only one there is
    std::string predictions_dir;  ///< EMSANet `mapping` folder (pred_panoptic_{semantic,instance}/)
    std::string semantic_dir;     ///< GT folder override (see NicrOptions)
    std::string instance_dir;
    /// Which labels to write: "auto" (model if model is set, predictions if predictions_dir is
    /// set, else none), "predictions", "gt" (ground truth with score 1), "model", "none".
    std::string labels = "auto";

    // --- segmentation front-end (any format): label every frame with a network
    std::string model;  ///< model description file (pndt_seg, doc/segmentation.md); empty = none
    /// Gravity up in the pose's world frame ("x y z"), for the detector's floor / wall / ceiling;
    /// empty = the camera's −y (an upright camera).
    std::string up_world;
    /// Write the poses in a world whose z is up: the world is turned about its origin so that
    /// up_world (or, without it, the world axis nearest the first written frame's up: the robot's
    /// z with a sensor_pose, else the camera's -y) becomes +z (the floor plan, pndt-nav's grid and
    /// MRPT's 2D tools take world z as up). A world already z-up is not turned.
    /// A ground truth in the source's world no longer lines up with the map.
    bool level = false;

    // --- all formats
    std::optional<double> depth_units_per_metre;  ///< default: the format's (mm; TUM 5000)
    double frame_rate_hz = 30.0;                  ///< stamps of stampless sequences: i / rate
    std::string intrinsics_file;  ///< Open3D intrinsics JSON overriding the folder's (redwood, tum)

    // --- poses (default: the sequence's own)
    std::string poses_file;   ///< external pose file (or nicr extrinsics folder)
    std::string pose_format;  ///< required with poses_file: tum, rtabmap0..11, redwood, nicr, ...
    /// What the external poses are poses of: "auto", "camera" (optical camera frame) or "robot"
    /// (body frame: x fwd, y left, z up; camera = robot ⊕ sensor_pose). auto: robot for RTAB-Map
    /// formats (`rtabmap-export --poses`), camera for the others.
    std::string pose_frame = "auto";
    /// How frames find their pose: "time" (interpolated at the frame stamp, SLERP, within
    /// max_pose_gap) or "index" (frame i ↔ pose i + pose_index_offset, exact). auto: index for
    /// stampless formats (rtabmap0, rtabmap2, rtabmap4 = vertex id, kitti, redwood), else time
    /// (nicr: t = frame number / frame rate, as the sequence's frames).
    std::string pose_match = "auto";
    double max_pose_gap = 0.1;      ///< seconds between the two poses bracketing a frame
    double pose_time_offset = 0.0;  ///< added to frame stamps before the lookup (time mode)
    int64_t pose_index_offset = 0;  ///< index mode
    bool strict_poses = false;      ///< non-finite poses are errors (file + line), not skips
    /// Robot → depth camera, MRPT sensor axes (x fwd, y left, z up). Written into every scan's
    /// sensorPose; the robot pose observation is then the robot's, not the camera's.
    mrpt::poses::CPose3D sensor_pose;

    // --- frame selection and output
    size_t start = 0;       ///< first frame (index into the sequence)
    size_t stride = 1;      ///< every stride-th frame
    size_t max_frames = 0;  ///< 0 = all
    bool color = true;      ///< embed the colour image when it is registered to the depth
    /// Colour images are stored JPEG-compressed at this quality (1..100); 0 = raw (lossless,
    /// ~0.9 MB per 640x480 frame). MRPT 2.5.8 stores raw unless told otherwise.
    int color_jpeg_quality = 95;
    bool skip_bad_frames = false;  ///< unreadable / wrong-size frame images: count and skip
    /// Added to every written stamp (not to the pose lookup), e.g. to give a stampless Redwood
    /// sequence (t = i / frame rate, i.e. 1970-01-01) a real start time.
    double stamp_offset = 0.0;
    std::string rgbd_label = "RGBD";
    std::string pose_label = "GT_POSE";
    int gz_level = 1;
};

/// What a conversion did.
struct ConvertReport
{
    std::string kind;         ///< redwood, tum, nicr
    std::string source;       ///< folder actually read
    std::string pose_source;  ///< "sequence (trajectory.log)" or "<file> (<format>, <match>)"
    size_t frames_in_source = 0;
    size_t frames_selected = 0;  ///< after start/stride/max
    size_t frames_written = 0;
    size_t frames_with_labels = 0;
    size_t frames_labels_missing = 0;  ///< labels expected but absent for the frame → geometry only
    size_t frames_instances_missing = 0;  ///< ground truth: a semantic image without its instance image
    size_t frames_with_color = 0;
    /// Skipped frames by reason ("no pose: ...", "unreadable frame").
    std::map<std::string, size_t> skipped;
    std::vector<std::string> skip_examples;  ///< first few skipped frames with their reason
    size_t non_finite_poses = 0;             ///< in the pose source (ignored)
    std::vector<std::string> notes;          ///< e.g. why colour was not embedded
    /// With `level`: the source world's up that became +z, and the turn in degrees; without
    /// --up, the first frame's up it was taken from (levelled_up is its nearest world axis).
    std::optional<Eigen::Vector3d> levelled_up;
    std::optional<Eigen::Vector3d> level_observed;
    double level_degrees = 0;
    // --- segmentation front-end (with --model)
    std::string segmenter;                  ///< describe() of the front-end
    size_t frames_segmented = 0;
    double segment_preprocess_ms = 0, segment_network_ms = 0, segment_postprocess_ms = 0;  ///< sums
    /// Detector mode: detections per map class (after the class mapping; "ignored" = class 0).
    std::map<std::string, size_t> detections_per_class;
    /// Frames with thing instances per map class name, summed over frames.
    std::map<std::string, size_t> instances_per_class;
    double seconds = 0;
    uint64_t output_bytes = 0;
    size_t skippedTotal() const;
};

/// Progress callback: (frames processed, frames selected).
using ProgressFn = std::function<void(size_t, size_t)>;

/// Runs a conversion. Throws pndt::InputError for bad input, std::runtime_error for I/O errors.
ConvertReport convertSequence(const ConvertOptions& options, const ProgressFn& progress = {});

/// Human-readable summary (several lines, no trailing newline).
std::string formatReport(const ConvertReport& r, const ConvertOptions& o);
/// The same as JSON text.
std::string reportJson(const ConvertReport& r, const ConvertOptions& o);

/// "x y z" → unit direction; throws InputError naming `option` unless three finite numbers, not
/// all zero.
Eigen::Vector3d parseUpDirection(const std::string& text, const std::string& option = "--up");

/// "x y z yaw pitch roll" (metres, degrees) → pose; throws InputError on anything else.
mrpt::poses::CPose3D parseSensorPose(const std::string& text);

}  // namespace pndt::convert
