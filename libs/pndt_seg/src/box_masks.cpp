#include "box_masks.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pndt::seg
{
namespace
{
bool validDepth(float z) { return z > 0 && std::isfinite(z); }
}  // namespace

int BoxMaskGrower::medianPixel(const Image<float>& depth, int x0, int y0, int x1, int y1, uint32_t claimable,
                               const std::vector<uint32_t>& owner)
{
    const auto candidate = [&](size_t i) {
        return validDepth(depth.data[i]) && (owner[i] == 0 || owner[i] == claimable);
    };
    window_.clear();
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            if (const size_t i = size_t(y) * depth.width + x; candidate(i)) window_.push_back(depth.data[i]);
    if (window_.empty()) return -1;
    std::nth_element(window_.begin(), window_.begin() + long(window_.size() / 2), window_.end());
    const float median = window_[window_.size() / 2];
    // The candidate nearest to the median, first in raster order.
    int seed = -1;
    float best = std::numeric_limits<float>::infinity();
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
        {
            const size_t i = size_t(y) * depth.width + x;
            if (!candidate(i)) continue;
            const float e = std::abs(depth.data[i] - median);
            if (e < best) best = e, seed = int(i);
        }
    return seed;
}

int BoxMaskGrower::findSeed(const Image<float>& depth, int x0, int y0, int x1, int y1, uint32_t claimable,
                            const std::vector<uint32_t>& owner)
{
    constexpr uint32_t kNone = 0;  // "claimable" value that admits free pixels only
    // 1. A small window at the box centre, when most of it is free valid depth.
    const int bw = x1 - x0, bh = y1 - y0;
    const int half = std::clamp(std::min(bw, bh) / 20, 1, 4);  // 3x3 .. 9x9
    const int cx = x0 + bw / 2, cy = y0 + bh / 2;
    const int wx0 = std::max(x0, cx - half), wx1 = std::min(x1, cx + half + 1);
    const int wy0 = std::max(y0, cy - half), wy1 = std::min(y1, cy + half + 1);
    int free_pixels = 0;
    for (int y = wy0; y < wy1; ++y)
        for (int x = wx0; x < wx1; ++x)
            if (const size_t i = size_t(y) * depth.width + x; owner[i] == 0 && validDepth(depth.data[i])) ++free_pixels;
    if (2 * free_pixels > (wx1 - wx0) * (wy1 - wy0)) return medianPixel(depth, wx0, wy0, wx1, wy1, kNone, owner);
    // 2. The box's central third: its free pixels, else (a picture on a wall) its wall pixels too.
    const int cw = std::max(1, bw / 3), ch = std::max(1, bh / 3);
    const int tx0 = x0 + (bw - cw) / 2, ty0 = y0 + (bh - ch) / 2;
    const int seed = medianPixel(depth, tx0, ty0, tx0 + cw, ty0 + ch, kNone, owner);
    return seed >= 0 ? seed : medianPixel(depth, tx0, ty0, tx0 + cw, ty0 + ch, claimable, owner);
}

size_t BoxMaskGrower::grow(const Image<float>& depth, const Detection& b, uint32_t id, double depth_step,
                           double footprints, double focal, double min_share, uint32_t claimable,
                           std::vector<uint32_t>& owner)
{
    queue_.clear();
    const float relative_step = float(std::max(depth_step, footprints / focal));
    const auto free = [&](size_t i) { return owner[i] == 0 || owner[i] == claimable; };
    const int W = depth.width, H = depth.height;
    const int x0 = std::clamp(int(std::floor(b.x0)), 0, W), x1 = std::clamp(int(std::ceil(b.x1)), 0, W);
    const int y0 = std::clamp(int(std::floor(b.y0)), 0, H), y1 = std::clamp(int(std::ceil(b.y1)), 0, H);
    if (x1 <= x0 || y1 <= y0) return 0;

    const int seed = findSeed(depth, x0, y0, x1, y1, claimable, owner);
    if (seed < 0) return 0;

    // Breadth-first over the box; pixels queued as packed (x, y) (no division per pixel).
    const auto pack = [](int x, int y) { return uint32_t(x) | uint32_t(y) << 16; };
    previous_.clear();
    frontier_.clear();
    frontier_.push_back(pack(seed % W, seed / W));
    previous_.push_back(owner[size_t(seed)]);
    owner[size_t(seed)] = id;
    for (size_t head = 0; head < frontier_.size(); ++head)
    {
        const int x = int(frontier_[head] & 0xFFFFu), y = int(frontier_[head] >> 16);
        const size_t i = size_t(y) * W + x;
        const float z = depth.data[i];
        const float limit = relative_step * z;
        const auto visit = [&](int qx, int qy, size_t j) {
            if (!free(j)) return;
            const float zj = depth.data[j];
            if (!validDepth(zj) || std::abs(zj - z) >= limit) return;
            previous_.push_back(owner[j]);
            owner[j] = id;
            frontier_.push_back(pack(qx, qy));
        };
        if (x > x0) visit(x - 1, y, i - 1);
        if (x + 1 < x1) visit(x + 1, y, i + 1);
        if (y > y0) visit(x, y - 1, i - size_t(W));
        if (y + 1 < y1) visit(x, y + 1, i + size_t(W));
    }
    const size_t n = frontier_.size();
    const double area = double(x1 - x0) * double(y1 - y0);
    if (double(n) < min_share * area)
    {
        for (size_t k = 0; k < n; ++k)
            owner[size_t(frontier_[k] >> 16) * W + (frontier_[k] & 0xFFFFu)] = previous_[k];
        return 0;
    }
    queue_.resize(n);
    for (size_t k = 0; k < n; ++k) queue_[k] = int((frontier_[k] >> 16) * uint32_t(W) + (frontier_[k] & 0xFFFFu));
    return n;
}

}  // namespace pndt::seg
