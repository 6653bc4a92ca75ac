#include <pndt/seg/panoptic_postprocess.h>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "fast_exp.h"

namespace pndt::seg
{
PanopticPostprocessor::PanopticPostprocessor(const ClassSet& classes, std::vector<uint16_t> channel_to_class,
                                             PostprocessOptions options)
    : classes_(classes), channel_to_class_(std::move(channel_to_class)), options_(options)
{
    if (options_.nms_kernel < 1 || options_.nms_kernel % 2 == 0)
        throw InputError(fmt::format("postprocess: nms_kernel must be odd and >= 1 (got {})", options_.nms_kernel));
    if (options_.top_k < 1) throw InputError(fmt::format("postprocess: top_k must be >= 1 (got {})", options_.top_k));
    if (channel_to_class_.empty() || channel_to_class_.size() > 256)
        throw InputError(fmt::format("postprocess: {} semantic channels (1..256 supported)", channel_to_class_.size()));
    for (uint16_t c : channel_to_class_)
    {
        if (!classes_.contains(c))
            throw InputError(fmt::format("postprocess: class id {} is outside the class set (0..{})", c,
                                         classes_.size() - 1));
        channel_is_thing_.push_back(classes_.isThing(c) ? 1 : 0);
    }
}

void PanopticPostprocessor::run(const PanopticTensors& t, PanopticFrame& out)
{
    if (t.width <= 0 || t.height <= 0 || !t.semantic)
        throw InputError(fmt::format("postprocess: empty semantic output ({}x{})", t.width, t.height));
    if (t.classes != int(channel_to_class_.size()))
        throw InputError(fmt::format("postprocess: the semantic output has {} channels but the model description "
                                     "names {} classes",
                                     t.classes, channel_to_class_.size()));
    if (t.center && !t.offset) throw InputError("postprocess: a centre heatmap needs an offset output");

    semanticArgmax(t);
    if (!t.center)
    {
        out.semantic = semantic_;
        out.semantic_score = semantic_score_;
        out.instance = {};
        out.panoptic_score = {};
        centers_.clear();
        return;
    }
    findCenters(t);
    groupThingPixels(t);

    // Eq. 1: a thing pixel of instance z takes z's majority thing class (ties: smaller id).
    const size_t C = classes_.size(), K = centers_.size(), N = size_t(t.width) * t.height;
    std::vector<uint32_t>& votes = votes_;
    votes.assign(K * C, 0);
    for (size_t i = 0; i < N; ++i)
        if (const uint32_t z = instance_.data[i]) ++votes[(z - 1) * C + semantic_.data[i]];
    majority_.assign(K, 0);
    for (size_t k = 0; k < K; ++k)
    {
        const uint32_t* v = &votes[k * C];
        uint16_t best = 0;
        for (size_t c = 1; c < C; ++c)
            if (v[c] > v[best]) best = uint16_t(c);
        majority_[k] = best;
    }
    out.semantic.resize(t.width, t.height);
    out.semantic_score.resize(t.width, t.height);
    out.instance.resize(t.width, t.height);
    out.panoptic_score.resize(t.width, t.height);
    for (size_t i = 0; i < N; ++i)
    {
        const uint32_t z = instance_.data[i];
        out.semantic.data[i] = z ? majority_[z - 1] : semantic_.data[i];
        out.semantic_score.data[i] = semantic_score_.data[i];
        out.instance.data[i] = z;
        out.panoptic_score.data[i] = z ? semantic_score_.data[i] * centers_[z - 1].score : 0.f;
    }
}

// The hot loops, as free functions compiled twice (AVX2 + FMA, and the baseline) and picked at
// load time by the CPU: a Debian binary cannot assume AVX2, most robots' CPUs have it.
#if defined(__x86_64__) && defined(__GNUC__)
#define PNDT_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define PNDT_SIMD_CLONES
#endif

namespace
{
/// Running max and argmax over the channels of pixels [b0, b0 + n) of planar logits.
PNDT_SIMD_CLONES void blockArgmax(const float* semantic, size_t N, int C, size_t b0, size_t n,
                                  float* __restrict mx, int32_t* __restrict am)
{
    const float* first = semantic + b0;
    for (size_t i = 0; i < n; ++i)
    {
        mx[i] = first[i];
        am[i] = 0;
    }
    for (int c = 1; c < C; ++c)
    {
        const float* __restrict p = semantic + size_t(c) * N + b0;
        for (size_t i = 0; i < n; ++i)
        {
            const float v = p[i], m = mx[i];
            const int32_t take = -int32_t(v > m);
            am[i] = (c & take) | (am[i] & ~take);
            mx[i] = v > m ? v : m;
        }
    }
}

/// S^L = softmax of the winner = 1 / Σ_c exp(l_c − l_max); `sum` is scratch of n floats.
PNDT_SIMD_CLONES void blockSoftmaxScore(const float* semantic, size_t N, int C, size_t b0, size_t n,
                                        const float* __restrict mx, float* __restrict sum, float* __restrict score)
{
    for (size_t i = 0; i < n; ++i) sum[i] = 0.f;
    for (int c = 0; c < C; ++c)
    {
        const float* __restrict p = semantic + size_t(c) * N + b0;
        for (size_t i = 0; i < n; ++i) sum[i] += fastExpNonPositive(p[i] - mx[i]);
    }
    for (size_t i = 0; i < n; ++i) score[i] = 1.f / sum[i];
}

/// Index + 1 of the centre nearest to each (px, py); centres outer, pixels inner (vectorised).
PNDT_SIMD_CLONES void blockNearestCentre(const float* __restrict px, const float* __restrict py, size_t n,
                                         const float* __restrict cx, const float* __restrict cy, size_t K,
                                         float* __restrict best_d, int32_t* __restrict best_k)
{
    for (size_t i = 0; i < n; ++i)
    {
        best_d[i] = std::numeric_limits<float>::infinity();
        best_k[i] = 0;
    }
    for (size_t k = 0; k < K; ++k)
    {
        const float x = cx[k], y = cy[k];
        const int32_t id = int32_t(k + 1);
        for (size_t i = 0; i < n; ++i)
        {
            const float ex = px[i] - x, ey = py[i] - y;
            const float d = ex * ex + ey * ey;
            const int32_t take = -int32_t(d < best_d[i]);  // strict: ties keep the earlier centre
            best_k[i] = (id & take) | (best_k[i] & ~take);
            best_d[i] = d < best_d[i] ? d : best_d[i];
        }
    }
}

// Pixel blocks small enough that their slices of all channels stay in L2 between passes.
constexpr size_t kBlock = 2048;
}  // namespace

void PanopticPostprocessor::semanticArgmax(const PanopticTensors& t)
{
    const size_t N = size_t(t.width) * t.height;
    argmax_.resize(N);
    max_logit_.resize(N);
    exp_sum_.resize(kBlock);
    semantic_score_.resize(t.width, t.height);
    for (size_t b0 = 0; b0 < N; b0 += kBlock)
    {
        const size_t n = std::min(kBlock, N - b0);
        blockArgmax(t.semantic, N, t.classes, b0, n, max_logit_.data() + b0, argmax_.data() + b0);
        float* score = semantic_score_.data.data() + b0;
        if (options_.semantic_is_logit)
            blockSoftmaxScore(t.semantic, N, t.classes, b0, n, max_logit_.data() + b0, exp_sum_.data(), score);
        else
            for (size_t i = 0; i < n; ++i) score[i] = std::clamp(max_logit_[b0 + i], 0.f, 1.f);
    }
    semantic_.resize(t.width, t.height);
    for (size_t i = 0; i < N; ++i)
    {
        if (!std::isfinite(max_logit_[i]) || !std::isfinite(semantic_score_.data[i]))
            throw InputError(fmt::format("postprocess: non-finite semantic output at pixel ({}, {})",
                                         i % size_t(t.width), i / size_t(t.width)));
        semantic_.data[i] = channel_to_class_[size_t(argmax_[i])];
    }
}

void PanopticPostprocessor::findCenters(const PanopticTensors& t)
{
    const size_t N = size_t(t.width) * t.height;
    center_prob_.resize(N);
    for (size_t i = 0; i < N; ++i)
    {
        const float v = t.center[i];
        center_prob_[i] = options_.center_is_logit ? 1.f / (1.f + std::exp(-v)) : v;
    }
    // A centre is the maximum of its nms_kernel window (max-pool == value) above the threshold.
    center_max_.resize(N);
    const cv::Mat prob(t.height, t.width, CV_32F, center_prob_.data());
    cv::Mat pooled(t.height, t.width, CV_32F, center_max_.data());
    cv::dilate(prob, pooled, cv::getStructuringElement(cv::MORPH_RECT, {options_.nms_kernel, options_.nms_kernel}),
               {-1, -1}, 1, cv::BORDER_CONSTANT, cv::Scalar(-std::numeric_limits<float>::infinity()));
    centers_.clear();
    for (int y = 0; y < t.height; ++y)
        for (int x = 0; x < t.width; ++x)
        {
            const size_t i = size_t(y) * t.width + x;
            const float v = center_prob_[i];
            if (v > options_.center_threshold && v >= center_max_[i]) centers_.push_back({x, y, std::min(v, 1.f)});
        }
    // Highest first; ties in raster order (stable), so equal plateaus give one id order.
    std::stable_sort(centers_.begin(), centers_.end(),
                     [](const InstanceCenter& a, const InstanceCenter& b) { return a.score > b.score; });
    if (int(centers_.size()) > options_.top_k) centers_.resize(size_t(options_.top_k));
}

void PanopticPostprocessor::groupThingPixels(const PanopticTensors& t)
{
    const size_t N = size_t(t.width) * t.height;
    instance_.resize(t.width, t.height, 0);
    const size_t K = centers_.size();
    if (K == 0) return;
    const float* dy = options_.offset_yx ? t.offset : t.offset + N;
    const float* dx = options_.offset_yx ? t.offset + N : t.offset;
    const float s = options_.offset_scale;
    centre_x_.resize(K);
    centre_y_.resize(K);
    for (size_t k = 0; k < K; ++k)
    {
        centre_x_[k] = float(centers_[k].x);
        centre_y_[k] = float(centers_[k].y);
    }
    vote_x_.resize(kBlock);
    vote_y_.resize(kBlock);
    best_d_.resize(kBlock);
    best_k_.resize(kBlock);
    for (size_t b0 = 0; b0 < N; b0 += kBlock)
    {
        const size_t n = std::min(kBlock, N - b0);
        // Each pixel votes for the point pixel + offset; it joins the centre nearest to it.
        size_t x = b0 % size_t(t.width), y = b0 / size_t(t.width);  // walked, not divided per pixel
        for (size_t i = 0; i < n; ++i)
        {
            const size_t j = b0 + i;
            vote_x_[i] = float(x) + s * dx[j];
            vote_y_[i] = float(y) + s * dy[j];
            if (++x == size_t(t.width))
            {
                x = 0;
                ++y;
            }
        }
        blockNearestCentre(vote_x_.data(), vote_y_.data(), n, centre_x_.data(), centre_y_.data(), K, best_d_.data(),
                           best_k_.data());
        for (size_t i = 0; i < n; ++i)
            instance_.data[b0 + i] = channel_is_thing_[size_t(argmax_[b0 + i])] ? uint32_t(best_k_[i]) : 0u;
    }
}

void resizeLabels(const PanopticFrame& in, int width, int height, PanopticFrame& out)
{
    if (width <= 0 || height <= 0) throw InputError(fmt::format("resizeLabels: bad size {}x{}", width, height));
    const int W = in.semantic.width, H = in.semantic.height;
    const bool instances = in.hasInstances();
    out.semantic.resize(width, height);
    out.semantic_score.resize(width, height);
    if (instances)
    {
        out.instance.resize(width, height);
        out.panoptic_score.resize(width, height);
    }
    else
    {
        out.instance = {};
        out.panoptic_score = {};
    }
    // Source pixel of a target pixel centre: floor((x + 0.5) · W / width).
    for (int y = 0; y < height; ++y)
    {
        const int sy = std::min(H - 1, int((y + 0.5) * H / height));
        for (int x = 0; x < width; ++x)
        {
            const int sx = std::min(W - 1, int((x + 0.5) * W / width));
            out.semantic.at(y, x) = in.semantic.at(sy, sx);
            out.semantic_score.at(y, x) = in.semantic_score.at(sy, sx);
            if (instances)
            {
                out.instance.at(y, x) = in.instance.at(sy, sx);
                out.panoptic_score.at(y, x) = in.panoptic_score.at(sy, sx);
            }
        }
    }
}

}  // namespace pndt::seg
