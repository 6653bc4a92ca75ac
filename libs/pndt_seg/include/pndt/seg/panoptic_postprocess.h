// Panoptic post-processing of an EMSANet / Panoptic-DeepLab style network, in C++:
// softmax → class and S^L; centre NMS (threshold, kernel, top-k); offset grouping of thing pixels
// to their nearest predicted centre; S^Z = the centre's heatmap score; the paper's Eq. 1 merge
// (an instance's pixels take its majority thing class) and S^P = S^L·S^Z (core panopticMerge).
#pragma once

#include <pndt/class_set.h>
#include <pndt/frame.h>

#include <cstdint>
#include <vector>

namespace pndt::seg
{
struct PostprocessOptions
{
    float center_threshold = 0.1f;   ///< heatmap peaks at or below are no centres
    int nms_kernel = 17;             ///< odd window (output pixels) a centre must be the maximum of
    int top_k = 64;                  ///< at most this many centres, highest first
    bool center_is_logit = false;    ///< "center_activation": "sigmoid" (we apply it) | "none"
    bool semantic_is_logit = true;   ///< "semantic_activation": "softmax" (we apply it) | "none"
    bool offset_yx = true;           ///< "offset_order": "yx" (Panoptic-DeepLab) | "xy"
    float offset_scale = 1.0f;       ///< offset value × scale = output pixels, pixel → its centre
};

/// Planar float32 network outputs at one resolution (width × height).
struct PanopticTensors
{
    int width = 0, height = 0;
    int classes = 0;
    const float* semantic = nullptr;  ///< [classes][height][width]
    const float* center = nullptr;    ///< [height][width]; nullptr = semantic-only
    const float* offset = nullptr;    ///< [2][height][width]; required with center
};

struct InstanceCenter
{
    int x = 0, y = 0;   ///< output pixel
    float score = 0;    ///< S^Z in [0, 1]
};

/// Reusable post-processor: after the first frame of a size it allocates nothing.
class PanopticPostprocessor
{
   public:
    /// `channel_to_class[c]` = class id (in `classes`) of semantic channel c.
    PanopticPostprocessor(const ClassSet& classes, std::vector<uint16_t> channel_to_class,
                          PostprocessOptions options);

    /// Label images at the tensors' resolution into out.semantic / semantic_score / instance /
    /// panoptic_score (instance images empty for semantic-only tensors). Instance ids are
    /// 1..centres in centre order (highest score first). Throws InputError on size mismatches.
    void run(const PanopticTensors& tensors, PanopticFrame& out);

    /// The centres the last run() kept (after NMS and top-k), highest score first.
    const std::vector<InstanceCenter>& centers() const { return centers_; }

   private:
    void semanticArgmax(const PanopticTensors& t);
    void findCenters(const PanopticTensors& t);
    void groupThingPixels(const PanopticTensors& t);

    const ClassSet& classes_;
    std::vector<uint16_t> channel_to_class_;
    std::vector<uint8_t> channel_is_thing_;
    PostprocessOptions options_;

    Image<uint16_t> semantic_;
    Image<float> semantic_score_;
    Image<uint32_t> instance_;
    Image<float> instance_score_;
    std::vector<int32_t> argmax_;  ///< winning channel per pixel (32-bit: vectorises with the floats)
    std::vector<float> max_logit_, exp_sum_, center_max_, center_prob_;
    std::vector<InstanceCenter> centers_;
    std::vector<float> centre_x_, centre_y_, vote_x_, vote_y_, best_d_;  ///< grouping scratch
    std::vector<int32_t> best_k_;
    std::vector<uint32_t> votes_;     ///< [centre][class] thing-pixel counts (Eq. 1)
    std::vector<uint16_t> majority_;  ///< per centre
};

/// Nearest-neighbour resampling of the four label images of `in` to width × height into `out`
/// (pixel centres aligned, like cv::INTER_NEAREST_EXACT); the depth and K of `out` are untouched.
void resizeLabels(const PanopticFrame& in, int width, int height, PanopticFrame& out);

}  // namespace pndt::seg
