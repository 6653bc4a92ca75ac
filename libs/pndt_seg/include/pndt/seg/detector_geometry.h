// The "detector + geometry" front-end's pure parts: CenterNet decoding, COCO → class-set
// mapping, instance masks from the depth segment inside each box, and floor / wall / ceiling
// from depth planes and gravity. No network code here (detector_segmenter.cpp runs the net).
#pragma once

#include <pndt/class_set.h>
#include <pndt/frame.h>
#include <pndt/types.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace pndt::seg
{
/// One detected object, box in pixels of the image it was scaled to: [x0, x1) × [y0, y1).
struct Detection
{
    int model_class = 0;  ///< channel of the detector's heatmap
    float score = 0;      ///< heatmap peak value in [0, 1]
    float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct CenterNetDecodeOptions
{
    float score_threshold = 0.3f;  ///< peaks below are ignored
    int top_k = 50;                ///< at most this many detections, highest score first
    int stride = 4;                ///< input pixels per heatmap cell
    float box_scale = 1.0f;        ///< box_size value × box_scale = distance in input pixels
};

/// CenterNet outputs → detections: 3×3 local maxima of each class channel of `heatmap`
/// ([classes][grid_h][grid_w], sigmoid scores) above the threshold; box = centre (stride·(x,y))
/// minus/plus the (left, top, right, bottom) distances in `box_size` ([4][grid_h][grid_w]),
/// in input pixels, then scaled from the input size to image_w × image_h and clipped to it.
/// Sorted by score (descending), ties by class then position, at most top_k.
std::vector<Detection> decodeCenterNet(const float* heatmap, int classes, int grid_h, int grid_w,
                                       const float* box_size, int input_w, int input_h, int image_w,
                                       int image_h, const CenterNetDecodeOptions& options);

/// Detector class names (e.g. COCO's "couch") → ids in `classes` (e.g. NYUv2-40 "sofa").
/// Built-in COCO → NYUv2-40 table (chair→chair, couch→sofa, bed→bed, dining table→table,
/// tv→television, toilet→toilet, refrigerator→refrigerator, sink→sink, book→books, ...), then
/// `overrides` (detector name → class name, "" or "void" = ignore the detection); names in
/// neither map to "otherprop" when `classes` has it, else to 0 (ignored). Every target class must
/// be a thing class of `classes`; throws InputError naming the class otherwise.
std::vector<uint16_t> mapDetectorClasses(const std::vector<std::string>& detector_names,
                                         const std::map<std::string, std::string>& overrides,
                                         const ClassSet& classes);

struct GeometryLabelOptions
{
    // --- stuff from planes (floor, ceiling, wall)
    int plane_sample_step = 4;          ///< pixel step of the points the planes are fitted to
    double plane_inlier_distance = 0.03;  ///< metres (grows with depth: × max(1, z / 2 m))
    double horizontal_tolerance_deg = 15;  ///< normal within this of gravity → floor / ceiling
    double vertical_tolerance_deg = 15;    ///< normal within this of horizontal → wall
    double min_plane_share = 0.03;      ///< of the frame's valid pixels, smaller planes are ignored
    int max_planes = 6;                 ///< at most 32 are used
    double min_wall_extent = 0.8;       ///< metres; a vertical plane smaller than this is no wall
    uint32_t ransac_iterations = 200;
    uint64_t seed = 1;                  ///< RANSAC is deterministic for a seed

    // --- instances from boxes
    /// A depth step between neighbours ends a depth segment when it exceeds both
    /// segment_depth_step × z and segment_footprints pixel footprints (z / f): the first absorbs
    /// sensor quantisation, the second keeps surfaces seen at grazing angles (a table top) whole.
    double segment_depth_step = 0.04;
    double segment_footprints = 8;
    double min_mask_share = 0.05;       ///< a mask covering less of its box is dropped
};

/// What label() found, for reports.
struct GeometryLabelStats
{
    int planes_floor = 0, planes_ceiling = 0, planes_wall = 0;
    int detections_used = 0, detections_dropped = 0;
};

/// Label images from detections + geometry, the depth image's size:
///  - stuff: pixels within the inlier distance t of a floor / ceiling / wall plane get that
///    class with S^L = a · (1 − ½ (r / t)²) for a pixel at distance r from the plane (0.5..1),
///    a = how well the plane's normal agrees with gravity (|cos| to up for floor / ceiling, |sin|
///    for walls); instance 0, S^P = 0. Only the lowest horizontal plane below the camera is
///    floor (not a table top), the highest above it ceiling;
///  - things: each detection (class mapped by `detector_to_class`, 0 = ignored) becomes one
///    instance: the connected depth segment at the box centre's depth inside the box, minus
///    stuff pixels (the seed: the median depth of a small window at the box centre, or of the
///    non-stuff pixels of the box's central third when the window is mostly stuff / invalid);
///    S^L = S^Z = the detection score, S^P = S^L·S^Z. Where masks overlap the
///    higher score wins. Instance ids are 1.. in score order within the frame;
///  - everything else: class 0 (void), score 0.
/// `up_cam` is the gravity "up" direction in the camera frame (unit vector); it decides which
/// planes are floor (below the camera, normal ∥ up), ceiling (above) and wall (normal ⊥ up).
/// Writes out.semantic / semantic_score / instance / panoptic_score; reuses their allocations.
class DetectorGeometryLabeller
{
   public:
    DetectorGeometryLabeller(const ClassSet& classes, std::vector<uint16_t> detector_to_class,
                             GeometryLabelOptions options = {});
    ~DetectorGeometryLabeller();
    GeometryLabelStats label(const Image<float>& depth, const CameraIntrinsics& K,
                             const Eigen::Vector3d& up_cam, const std::vector<Detection>& detections,
                             PanopticFrame& out);

   private:
    const ClassSet& classes_;
    std::vector<uint16_t> detector_to_class_;
    GeometryLabelOptions options_;
    int floor_ = 0, ceiling_ = 0, wall_ = 0;  ///< class ids (0 = the class set lacks it)
    struct Work;                              ///< plane finder, mask grower, buffers (reused)
    std::unique_ptr<Work> work_;
};

}  // namespace pndt::seg
