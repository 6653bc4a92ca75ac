// RGB-D sequence folders: Redwood/Open3D, TUM RGB-D, nicr-scene-analysis-datasets.
//
// Opening a sequence only indexes it (file paths, stamps, intrinsics, poses); images are decoded
// by RgbdSequence::load(i), one frame at a time (a 211-frame 640x480 sequence would need ~450 MB
// if decoded at once).
//
// Poses are T_world_cam with cam = the OpenCV optical frame of the depth camera (x right, y down,
// z forward), i.e. world_point = T_world_cam * K.unproject(col, row, depth).
#pragma once

#include <pndt/io/images.h>
#include <pndt/io/poses.h>
#include <pndt/types.h>

#include <optional>
#include <string>
#include <vector>

namespace pndt::io
{
/// One decoded frame.
struct RgbdFrame
{
    double t = 0;    ///< seconds (see the open* function for how it is derived)
    std::string id;  ///< file stem of the depth image (e.g. "00042")
    Image<float> depth;  ///< metres, 0 = invalid
    RgbImage color;      ///< RGB; empty if the sequence has no colour or it was not requested
    CameraIntrinsics K;        ///< depth camera; K.width/height == depth size
    CameraIntrinsics K_color;  ///< colour camera (equal to K for registered RGB-D data)
    std::optional<Pose> T_world_cam;  ///< optical depth camera → world; nullopt = no usable pose
    Image<uint16_t> semantic_gt;  ///< nicr only: ground-truth classes (empty if absent)
    Image<uint16_t> instance_gt;  ///< nicr only: ground-truth instance ids (empty if absent)
    Image<float> pred_semantic;   ///< nicr + predictions_dir: EMSANet class + score (empty if absent)
    Image<float> pred_instance;   ///< nicr + predictions_dir: EMSANet instance + score (empty if absent)
};

/// Index entry of one frame (no pixels).
struct FrameRecord
{
    double t = 0;
    std::string id;
    std::string depth_path;
    std::string color_path;          ///< empty = none
    std::string semantic_path;       ///< empty = none
    std::string instance_path;       ///< empty = none
    std::string pred_semantic_path;  ///< empty = none
    std::string pred_instance_path;  ///< empty = none
    CameraIntrinsics K;
    CameraIntrinsics K_color;
    std::optional<Pose> T_world_cam;
};

struct FrameLoadOptions
{
    bool color = true;
    bool labels = true;       ///< ground-truth semantic / instance images
    bool predictions = true;  ///< EMSANet .npz predictions
};

struct RgbdSequence
{
    std::string source;  ///< the folder that was opened
    std::string kind;    ///< "redwood", "tum" or "nicr"
    double depth_units_per_metre = kDepthUnitsMillimetre;
    std::vector<FrameRecord> frames;
    size_t frames_without_pose = 0;  ///< frames whose T_world_cam is nullopt (any reason)
    /// Poses present in the source but non-finite (ignored): Redwood/nicr = frames concerned,
    /// TUM = ground-truth lines skipped before interpolation.
    size_t non_finite_poses = 0;

    size_t size() const { return frames.size(); }
    /// Decodes frame i. Throws InputError naming the file if an image is missing, malformed or
    /// its size disagrees with the intrinsics; std::out_of_range for a bad index.
    RgbdFrame load(size_t i, const FrameLoadOptions& options = {}) const;
};

// --- Redwood / Open3D ------------------------------------------------------------------------
/// Folder layout: depth/*.png (uint16, mm), colour in color/ or image/ (or rgb/) as .jpg/.png,
/// camera_primesense.json (Open3D intrinsics), trajectory.log (optional; camera-to-world, optical).
/// Frames are the depth images sorted by name; colour images are paired by sorted order (counts
/// must match). If an Open3D `rgbd.match` file (`depth/x.png color/y.jpg` per line) exists, it
/// defines the frames and pairs instead. Frame i ↔ i-th .log block (counts must match);
/// t = i / frame_rate_hz.
struct RedwoodOptions
{
    double frame_rate_hz = 30.0;
    double depth_units_per_metre = kDepthUnitsMillimetre;
    std::string trajectory_file = "trajectory.log";          ///< relative to the folder
    std::string intrinsics_file = "camera_primesense.json";  ///< relative to the folder
    std::optional<CameraIntrinsics> intrinsics;  ///< overrides intrinsics_file when set
    bool non_finite_pose_is_error = false;       ///< default: frame gets no pose, counted
};
RgbdSequence openRedwoodSequence(const std::string& dir, const RedwoodOptions& options = {});

// --- TUM RGB-D --------------------------------------------------------------------------------
/// Folder layout: rgb/, depth/ (uint16 PNG, 5000 units per metre, registered to rgb), rgb.txt,
/// depth.txt, groundtruth.txt (TUM poses, optical colour camera → mocap world; optional).
/// Frames come from an association file (associate.py output `t_rgb rgb/x.png t_depth depth/y.png`
/// — the column holding a path under depth/ is taken as depth, else the order rgb, depth is
/// assumed — or Open3D's 2-column `depth color` rgbd.match). Without one, rgb.txt and depth.txt
/// are associated here: greedy nearest stamps within max_association_dt, each image used once.
/// t = depth stamp (2-column files: the depth file stem if it is a decimal timestamp such as
/// "1305031102.160407", else index / frame_rate_hz). Poses are interpolated at t (SLERP) with
/// max_pose_gap; frames outside the ground truth or in a larger gap get no pose (counted).
struct TumOptions
{
    std::string associations_file;  ///< relative to the folder; empty = auto (associations.txt,
                                    ///< association.txt, associate.txt, rgbd.match) or rgb/depth.txt
    double max_association_dt = 0.02;
    double depth_units_per_metre = kDepthUnitsTum;
    /// Default: TUM's documented values for all sequences (depth registered to the colour camera):
    /// 640x480, fx = fy = 525, cx = 319.5, cy = 239.5.
    std::optional<CameraIntrinsics> intrinsics;
    std::string groundtruth_file = "groundtruth.txt";  ///< relative; absent file = no poses
    double max_pose_gap = 0.1;                          ///< seconds
    double frame_rate_hz = 30.0;
};
RgbdSequence openTumSequence(const std::string& dir, const TumOptions& options = {});

// --- A recording folder by its layout ----------------------------------------------------------
/// True for a TUM RGB-D layout: rgb.txt + depth.txt, or an association file (associations.txt,
/// association.txt, associate.txt). Open3D's rgbd.match alone is Redwood's layout.
bool isTumFolder(const std::string& dir);
/// A Redwood or TUM folder with each layout's default options (isTumFolder tells which): what
/// the tools that take "a Redwood / TUM folder" open.
RgbdSequence openRecordingFolder(const std::string& dir);

// --- nicr-scene-analysis-datasets ----------------------------------------------------------------
/// Layout written by the nicr-scene-analysis-datasets preparation scripts (Hypersim, ScanNet),
/// relative to a split folder `<dataset>/<split>` (split = train | valid | test):
///   depth/<seq>/<frame>.png             uint16 depth, mm (Hypersim: z-depth, 0 = invalid/clipped)
///   rgb/<seq>/<frame>.png|.jpg          colour (Hypersim png, ScanNet jpg)
///   extrinsics/<seq>/<frame>.json       {x,y,z,quat_x,quat_y,quat_z,quat_w} camera→world, optical
///   depth_intrinsics/<seq>.json         {fx,fy,cx,cy} normalised (+ a, b for Hypersim)
///   rgb_intrinsics/<seq>.json           {fx,fy,cx,cy} normalised
///   semantic_40/<seq>/<frame>.png       Hypersim GT classes (uint8, NYUv2-40 + void)
///   semantic_<raw|refined>_<20|40|200|549>/<seq>/<frame>.png   ScanNet GT classes
///   instance/<seq>/<frame>.png          Hypersim GT: R = class, (G << 8) | B = instance id
///   instance_<raw|refined>/<seq>/<frame>.png                   ScanNet GT instance ids
/// where <seq> is `<scene>/<camera>` for Hypersim (e.g. `ai_001_010/cam_00`) and
/// `<camera>/<scene>` for ScanNet (e.g. `structureio_968x1296/scene0000_00`). The same
/// `<seq>/<frame>` identifier is used by EMSANet's mapping export:
///   <predictions_dir>/pred_panoptic_semantic/<seq>/<frame>.npz, pred_panoptic_instance/...
/// Depth and colour may differ in size and are not registered (ScanNet: 640x480 vs 1296x968);
/// nothing is resized here. Frames are the depth images sorted by name; t = frame number /
/// frame_rate_hz (ScanNet frame numbers index the 30 Hz stream; Hypersim has no time). A missing
/// extrinsics file or a non-finite one (ScanNet has a few) gives a frame without pose (counted).
struct NicrOptions
{
    double frame_rate_hz = 30.0;
    /// Default: 1 / `a` from the depth intrinsics if present, else 1000 (mm).
    std::optional<double> depth_units_per_metre;
    /// GT folders relative to the split folder; empty = auto-detect: semantic_40, then
    /// semantic_refined_40; instance, then instance_refined. "-" = do not use.
    std::string semantic_dir;
    std::string instance_dir;
    std::string predictions_dir;  ///< EMSANet `.../mapping` folder; empty = none
};
RgbdSequence openNicrSequence(const std::string& split_dir, const std::string& sequence,
                              const NicrOptions& options = {});
/// All `<seq>` identifiers under `<split_dir>/depth` (folders that contain .png files), sorted.
std::vector<std::string> listNicrSequences(const std::string& split_dir);

}  // namespace pndt::io
