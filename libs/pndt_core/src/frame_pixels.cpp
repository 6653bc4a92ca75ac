#include "frame_pixels.h"

#include <fmt/format.h>

#include <cmath>
#include <cstring>

namespace pndt
{
namespace
{
/// Rows of a possibly strided view, contiguous: in place when they already are.
template <typename T>
FrameImage<T> contiguousPixels(const ImageView<T>& v, std::vector<T>& buffer)
{
    FrameImage<T> out;
    if (v.empty()) return out;
    out.width = v.width;
    out.height = v.height;
    const size_t n = size_t(v.width) * size_t(v.height);
    if (v.contiguous())
    {
        out.data = {v.data, n};
        return out;
    }
    buffer.resize(n);
    for (int r = 0; r < v.height; ++r) std::memcpy(&buffer[size_t(r) * v.width], v.row(r), sizeof(T) * size_t(v.width));
    out.data = {buffer.data(), n};
    return out;
}

/// Length of the pixel's ray per metre of z.
double rayPerZ(const CameraIntrinsics& K, int r, int c)
{
    const double x = (c - K.cx) / K.fx, y = (r - K.cy) / K.fy;
    return std::sqrt(1.0 + x * x + y * y);
}
}  // namespace

FramePixels resolveFrame(const FrameView& v, const MapOptions& options, FrameInputBuffers& buffers)
{
    FramePixels f;
    f.K = v.K;
    f.source = v.source;
    const std::string where = f.where();
    const CameraIntrinsics& K = v.K;
    if (const std::string problem = K.invalidReason(); !problem.empty())
        throw InputError(fmt::format("{}: invalid camera intrinsics: {}", where, problem));
    if (K.width > 32767 || size_t(K.width) * size_t(K.height) >= (size_t(1) << 25))
        throw InputError(fmt::format("{}: a {}x{} image is too large (at most 32767 columns and 2^25 pixels)", where,
                                     K.width, K.height));
    const DepthView& d = v.depth;
    if (d.empty() || d.width != K.width || d.height != K.height)
        throw InputError(fmt::format("{}: depth image is {}x{}{} but the intrinsics are for {}x{}", where, d.width,
                                     d.height, d.empty() ? " (no pixels)" : "", K.width, K.height));
    if (d.rowStride() < size_t(d.width))
        throw InputError(fmt::format("{}: depth row stride {} is less than the width {}", where, d.stride, d.width));
    if (d.is_uint16 && !(d.metres_per_unit > 0 && std::isfinite(d.metres_per_unit)))
        throw InputError(fmt::format("{}: depth scale {} metres per unit is not positive", where, d.metres_per_unit));
    const auto checkView = [&](const auto& img, const char* what) {
        if (img.empty()) return;
        if (img.width != d.width || img.height != d.height)
            throw InputError(fmt::format("{}: {} image is {}x{} but the depth image is {}x{}", where, what, img.width,
                                         img.height, d.width, d.height));
        if (img.rowStride() < size_t(img.width))
            throw InputError(fmt::format("{}: {} row stride {} is less than the width {}", where, what, img.stride,
                                         img.width));
    };
    checkView(v.semantic, "semantic");
    checkView(v.semantic_score, "semantic score");
    checkView(v.instance, "instance");
    checkView(v.panoptic_score, "panoptic score");
    if (v.hasLabels() && v.semantic_score.empty())
        throw InputError(fmt::format("{}: semantic labels without semantic scores", where));
    if (v.hasInstances() && (v.panoptic_score.empty() || !v.hasLabels()))
        throw InputError(fmt::format("{}: instance ids need panoptic scores and semantic labels", where));

    const int W = d.width, H = d.height;
    const size_t n = size_t(W) * size_t(H);
    f.depth.width = W;
    f.depth.height = H;
    const bool ray_limit = options.max_range_along == RangeKind::Ray;
    if (!d.is_uint16 && d.measures == RangeKind::Z && !ray_limit && d.rowStride() == size_t(W))
        f.depth.data = {static_cast<const float*>(d.data), n};  // read in place
    else
    {
        // Over a ray limit: a z the projection counts as beyond max_range.
        const float beyond = float(options.max_range) * 2.f + 1.f;
        const double limit = options.max_range;
        buffers.depth.resize(n);
        for (int r = 0; r < H; ++r)
        {
            float* out = &buffers.depth[size_t(r) * W];
            if (d.is_uint16)
            {
                const uint16_t* in = static_cast<const uint16_t*>(d.data) + size_t(r) * d.rowStride();
                const float scale = float(d.metres_per_unit);
                for (int c = 0; c < W; ++c) out[c] = float(in[c]) * scale;  // 0 stays invalid
            }
            else
                std::memcpy(out, static_cast<const float*>(d.data) + size_t(r) * d.rowStride(), sizeof(float) * size_t(W));
            if (d.measures == RangeKind::Z && !ray_limit) continue;
            for (int c = 0; c < W; ++c)
            {
                const float value = out[c];
                if (!(value > 0.f) || !std::isfinite(value)) continue;  // invalid stays invalid
                const double per_z = rayPerZ(K, r, c);
                const double z = d.measures == RangeKind::Ray ? value / per_z : value;
                const double ray = d.measures == RangeKind::Ray ? value : value * per_z;
                out[c] = ray_limit && ray > limit ? beyond : float(z);
            }
        }
        f.depth.data = {buffers.depth.data(), n};
    }
    f.semantic = contiguousPixels(v.semantic, buffers.semantic);
    f.semantic_score = contiguousPixels(v.semantic_score, buffers.semantic_score);
    f.instance = contiguousPixels(v.instance, buffers.instance);
    f.panoptic_score = contiguousPixels(v.panoptic_score, buffers.panoptic_score);
    // Scores are probabilities: a network's logits (or 5.0 for "sure") would outvote every
    // later frame. One branch-free pass each (vectorised); the first bad pixel named.
    const auto checkScores = [&](const FrameImage<float>& image, const char* what) {
        const FrameSpan<float>& scores = image.data;
        const float* x = scores.data();
        const size_t n = scores.size();
        uint32_t bad = 0;  // bitwise, not &&: a short-circuit kept the loop scalar (0.3 ms a frame)
        for (size_t i = 0; i < n; ++i) bad |= (uint32_t(x[i] >= 0.f) & uint32_t(x[i] <= 1.f)) ^ 1u;  // NaN too
        if (!bad) return;
        for (size_t i = 0; i < scores.size(); ++i)
            if (!(scores[i] >= 0.f && scores[i] <= 1.f))
                throw InputError(fmt::format("{}: {} score {} at pixel (row {}, col {}) is not a probability (0 to 1)",
                                             where, what, scores[i], i / size_t(W), i % size_t(W)));
    };
    if (!v.scores_in_range)
    {
        checkScores(f.semantic_score, "semantic");
        checkScores(f.panoptic_score, "panoptic");
    }
    return f;
}
}  // namespace pndt
