// Panoptic post-processing of an EMSANet / Panoptic-DeepLab style network, in C++:
// softmax → class and S^L; centre NMS (threshold, kernel, top-k); offset grouping of thing pixels
// to their nearest predicted centre; S^Z = the centre's heatmap score; the paper's Eq. 1 merge
// (an instance's pixels take its majority thing class) and S^P = S^L·S^Z (core panopticMerge).
#pragma once

#include <pndt/class_set.h>
#include <pndt/frame.h>

#include <array>
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
    /// Bound on the relative error of S^L from the classes left out of its softmax sum: per
    /// 64-pixel block, a class whose logit is below every pixel's winner by more than
    /// T = ln((classes − 1) / score_tolerance) is skipped (its e^(l − l_max) < e^−T), so S^L is
    /// at most that fraction too high (plus < 3e-6 from the polynomial exp). 0 = never skip.
    float score_tolerance = 1e-4f;
    /// Widest vector kernel the pixel pass may use (the CPU's best by default). AVX-512 and
    /// AVX2 give the same labels and scores bit for bit, the scalar one the same labels and the
    /// scores to the polynomial exp's rounding; narrower ones are for measurements and tests.
    enum class Kernel
    {
        Best,
        Avx2,
        Scalar,
    };
    Kernel kernel = Kernel::Best;
};

/// Where the last run() spent its time (CPU time of the calling thread, milliseconds).
struct PostprocessTiming
{
    double centres_ms = 0;   ///< centre heatmap: NMS, threshold, top-k; the grouping's centre grid
    double pixels_ms = 0;    ///< one pass over the pixels: max/argmax, S^L, offset grouping of thing pixels
    double merge_ms = 0;     ///< Eq. 1: majority class per instance, written back to its pixels
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

    const PostprocessTiming& lastTiming() const { return timing_; }

   private:
    void findCenters(const PanopticTensors& t);
    void buildCentreGrid(int width, int height);
    uint32_t nearestCentre(float x, float y) const;
    void groupBlock(const PanopticTensors& t, size_t b0, size_t n, const int32_t* am, PanopticFrame& out);

    const ClassSet& classes_;
    std::vector<uint16_t> channel_to_class_;
    /// Per channel (all 256 a channel index can take, so vector kernels can gather them):
    /// 1 for a thing class, else 0; and its class id.
    std::array<int32_t, 256> channel_is_thing_{};
    std::array<int32_t, 256> channel_class_{};
    PostprocessOptions options_;

    PostprocessTiming timing_;
    // Per block of pixels: winning channel (32-bit: vectorises with the floats), max logit, Σ exp.
    std::vector<int32_t> argmax_;
    std::vector<float> max_logit_, exp_sum_;
    std::vector<float> center_max_, center_prob_;
    std::vector<InstanceCenter> centers_;
    std::vector<float> centre_x_, centre_y_;
    // Centre grid for the grouping: per cell of kGridCell² vote pixels, the centres that can be
    // nearest to a vote in it (ascending), as ranges of grid_ids_.
    float grid_x0_ = 0, grid_y0_ = 0;
    int grid_w_ = 0, grid_h_ = 0;
    std::vector<int32_t> grid_start_, grid_ids_;
    std::vector<uint32_t> grid_single_;  ///< per cell: its only candidate + 1, or "several"
    std::vector<float> centre_score_;    ///< S^Z per instance id (0: none)
    std::vector<double> scratch_d_;
    std::vector<uint32_t> votes_;          ///< [1 + centre][class] thing-pixel counts (Eq. 1)
    std::vector<uint16_t> majority_;       ///< per centre
    std::vector<uint8_t> block_has_instance_;
};

/// Nearest-neighbour resampling of the four label images of `in` to width × height into `out`
/// (pixel centres aligned, like cv::INTER_NEAREST_EXACT); the depth and K of `out` are untouched.
void resizeLabels(const PanopticFrame& in, int width, int height, PanopticFrame& out);

}  // namespace pndt::seg
