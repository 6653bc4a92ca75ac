// The segmentation front-end (paper Eq. 1, design §5): turns one RGB-D frame into the two
// panoptic label images a PanopticFrame carries (class + S^L, instance + S^P).
//
// Modes, chosen by the model description file (model_description.h):
//  - "panoptic": an EMSANet-style network (semantic logits, instance centre heatmap, centre
//    offsets) run through OpenCV DNN, post-processed in C++ (panoptic_postprocess.h);
//  - "semantic": the same without an instance head (semantic labels, no instances);
//  - "detector": a box detector (CenterNet, COCO-80) + geometry: instance masks from the depth
//    segment inside each box, floor / wall / ceiling from depth planes and gravity;
//  - geometry only: no segmenter at all (the frame keeps empty label images).
#pragma once

#include <pndt/class_set.h>
#include <pndt/frame.h>
#include <pndt/seg/detector_geometry.h>
#include <pndt/types.h>

#include <array>
#include <memory>
#include <optional>
#include <string>

namespace pndt::seg
{
using RgbPixel = std::array<uint8_t, 3>;

/// What a segmenter sees of a frame. The colour image must be registered to the depth image
/// (same size); nullptr = no colour (only depth-input models and geometry can run then).
struct SegmentationInput
{
    const Image<float>* depth = nullptr;       ///< metres along the optical axis, 0 = invalid
    const Image<RgbPixel>* color = nullptr;    ///< RGB, registered to depth
    CameraIntrinsics K;                        ///< of the depth image
    std::optional<Pose> T_world_cam;           ///< optical camera → world, if known (gravity)
    std::string source;                        ///< for error messages, e.g. "frame 00042"
};

/// Per-stage wall time of the last segment() call, milliseconds.
struct SegmentationTiming
{
    double preprocess_ms = 0;
    double network_ms = 0;
    double postprocess_ms = 0;
    double total() const { return preprocess_ms + network_ms + postprocess_ms; }
};

class Segmenter
{
   public:
    virtual ~Segmenter() = default;
    /// Writes frame.semantic / semantic_score / instance / panoptic_score (the depth image's size)
    /// and leaves frame.depth and frame.K alone. Throws InputError naming input.source for bad
    /// input (no colour for an RGB model, sizes that disagree).
    virtual void segment(const SegmentationInput& input, PanopticFrame& frame) = 0;
    /// One line: mode, model name, input size.
    virtual std::string describe() const = 0;
    const SegmentationTiming& lastTiming() const { return timing_; }
    /// The boxes of the last frame (detector mode; nullptr for other modes).
    virtual const std::vector<Detection>* lastDetections() const { return nullptr; }
    /// Detector mode: "couch -> sofa" for a detection's model_class ("" for other modes).
    virtual std::string detectionClassName(int model_class) const { return {}; }

   protected:
    SegmentationTiming timing_;
};

/// Settings of the recording rather than of the model.
struct SegmenterOptions
{
    /// Gravity "up" in the world frame of the poses (e.g. (0,0,1) for z-up maps, (0,−1,0) when
    /// the world is an upright first camera frame). Unset, or a frame without a pose: the
    /// camera's own −y axis (an upright camera) is taken as up.
    std::optional<Eigen::Vector3d> up_world;
};

/// Loads the model description file (JSON, model_description.h) and its ONNX network, checks
/// that the network has the inputs and outputs the description names and that its classes map
/// onto `classes`. Throws InputError naming the file and what is wrong (missing file, not ONNX,
/// missing output "center", unknown class "sofa2", ...).
/// The network is run once on a blank input at load time, so a wrong model (output missing or of
/// the wrong shape) fails here, not at the first frame. `classes` must outlive the segmenter.
std::unique_ptr<Segmenter> loadSegmenter(const std::string& description_path, const ClassSet& classes,
                                         const SegmenterOptions& options = {});

}  // namespace pndt::seg
