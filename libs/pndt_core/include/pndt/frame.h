// One RGB-D frame with its (optional) panoptic segmentation, as the core consumes it:
// PanopticFrame owns its images; FrameView points at the caller's buffers (a camera
// driver's uint16 millimetres, a cv::Mat, an MRPT range image) without copying them.
#pragma once

#include <pndt/types.h>

#include <string>
#include <string_view>

namespace pndt
{
/// Depth in metres along the optical axis (z, not the length of the pixel's ray;
/// 0, negative, NaN = invalid). The label images are optional (all empty = geometry
/// only); when present they have the depth image's size. Semantic class 0 = void;
/// instance 0 = none (things only).
struct PanopticFrame
{
    CameraIntrinsics K;
    Image<float> depth;
    Image<uint16_t> semantic;
    Image<float> semantic_score;   ///< S^L in [0,1]
    Image<uint32_t> instance;
    Image<float> panoptic_score;   ///< S^P = S^L * S^Z in [0,1]

    bool hasLabels() const { return !semantic.empty(); }
    bool hasInstances() const { return !instance.empty(); }
    /// Source description used in error messages (e.g. "RGBD @ 1700000000.123").
    std::string source;
    /// True when the scores are probabilities by construction (the label-image decode sets it:
    /// fractions of "id + score"): integrate() then skips its pass that refuses a score outside
    /// 0 to 1 (a memory-bound 0.1 ms a 640x480 frame). Leave it false for scores of your own.
    bool scores_in_range = false;
};

/// Row-major pixels the caller owns; `stride` = elements from one row to the next
/// (0 = width). Must stay valid while PanopticMap::integrate runs.
template <typename T>
struct ImageView
{
    const T* data = nullptr;
    int width = 0;
    int height = 0;
    size_t stride = 0;

    ImageView() = default;
    ImageView(const T* pixels, int w, int h, size_t row_stride = 0) : data(pixels), width(w), height(h), stride(row_stride) {}
    ImageView(const Image<T>& img)  // NOLINT: an owned image views implicitly
        : data(img.empty() ? nullptr : img.data.data()), width(img.width), height(img.height)
    {
    }
    bool empty() const { return data == nullptr; }
    size_t rowStride() const { return stride ? stride : size_t(width); }
    bool contiguous() const { return rowStride() == size_t(width); }
    const T* row(int r) const { return data + size_t(r) * rowStride(); }
};

/// A depth image in the caller's buffer: float metres or uint16 units with a scale.
struct DepthView
{
    const void* data = nullptr;
    int width = 0;
    int height = 0;
    size_t stride = 0;          ///< elements per row (0 = width)
    bool is_uint16 = false;     ///< else float32
    double metres_per_unit = 1; ///< uint16 only: 0.001 for millimetres, 0.0002 for TUM's 5000 per metre
    RangeKind measures = RangeKind::Z;

    /// Float metres (0, negative, NaN, inf = invalid).
    static DepthView metres(const float* pixels, int w, int h, size_t row_stride = 0, RangeKind kind = RangeKind::Z)
    {
        return {pixels, w, h, row_stride, false, 1.0, kind};
    }
    /// Unsigned 16-bit units (0 = invalid), metres = value × metres_per_unit.
    static DepthView units(const uint16_t* pixels, int w, int h, double metres_per_unit = 0.001, size_t row_stride = 0,
                           RangeKind kind = RangeKind::Z)
    {
        return {pixels, w, h, row_stride, true, metres_per_unit, kind};
    }
    bool empty() const { return data == nullptr; }
    size_t rowStride() const { return stride ? stride : size_t(width); }
};

/// A frame over the caller's buffers. The map copies nothing it can read in place:
/// float metres along z in a contiguous buffer are read directly; uint16 units, ray
/// lengths, strided rows and a max_range along rays are converted row by row into
/// buffers the map keeps between frames (no allocation once they have grown).
struct FrameView
{
    CameraIntrinsics K;
    DepthView depth;
    ImageView<uint16_t> semantic;
    ImageView<float> semantic_score;
    ImageView<uint32_t> instance;
    ImageView<float> panoptic_score;
    std::string_view source;  ///< for error messages; must outlive integrate()
    bool scores_in_range = false;  ///< as PanopticFrame::scores_in_range

    FrameView() = default;
    /// Views an owned frame (no copy).
    explicit FrameView(const PanopticFrame& f)
        : K(f.K),
          depth(DepthView::metres(f.depth.empty() ? nullptr : f.depth.data.data(), f.depth.width, f.depth.height)),
          semantic(f.semantic),
          semantic_score(f.semantic_score),
          instance(f.instance),
          panoptic_score(f.panoptic_score),
          source(f.source),
          scores_in_range(f.scores_in_range)
    {
    }
    bool hasLabels() const { return !semantic.empty(); }
    bool hasInstances() const { return !instance.empty(); }
};

}  // namespace pndt
