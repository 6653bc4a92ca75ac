#include "box_masks.h"

#include <algorithm>
#include <cmath>

namespace pndt::seg
{
namespace
{
bool validDepth(float z) { return z > 0 && std::isfinite(z); }
}  // namespace

size_t BoxMaskGrower::grow(const Image<float>& depth, const Detection& b, uint32_t id, double depth_step,
                           double footprints, double focal, double min_share, uint32_t claimable,
                           std::vector<uint32_t>& owner)
{
    const float relative_step = float(std::max(depth_step, footprints / focal));
    const auto free = [&](size_t i) { return owner[i] == 0 || owner[i] == claimable; };
    const int W = depth.width, H = depth.height;
    const int x0 = std::clamp(int(std::floor(b.x0)), 0, W), x1 = std::clamp(int(std::ceil(b.x1)), 0, W);
    const int y0 = std::clamp(int(std::floor(b.y0)), 0, H), y1 = std::clamp(int(std::ceil(b.y1)), 0, H);
    if (x1 <= x0 || y1 <= y0) return 0;

    // Seed: the valid pixel of the box's central third whose depth is the window's median.
    const int cw = std::max(1, (x1 - x0) / 3), ch = std::max(1, (y1 - y0) / 3);
    const int cx0 = x0 + (x1 - x0 - cw) / 2, cy0 = y0 + (y1 - y0 - ch) / 2;
    // Seed pixels: unlabelled ones first (the object), wall pixels only if there are none.
    int seed = -1;
    for (const bool with_wall : {false, true})
    {
        const auto candidate = [&](size_t i) {
            return validDepth(depth.data[i]) && (owner[i] == 0 || (with_wall && owner[i] == claimable));
        };
        window_.clear();
        for (int y = cy0; y < cy0 + ch; ++y)
            for (int x = cx0; x < cx0 + cw; ++x)
                if (candidate(size_t(y) * W + x)) window_.push_back(depth.at(y, x));
        if (window_.empty()) continue;
        std::nth_element(window_.begin(), window_.begin() + long(window_.size() / 2), window_.end());
        const float median = window_[window_.size() / 2];
        float best = 1e30f;
        for (int y = cy0; y < cy0 + ch; ++y)
            for (int x = cx0; x < cx0 + cw; ++x)
            {
                const size_t i = size_t(y) * W + x;
                if (!candidate(i)) continue;
                const float e = std::abs(depth.data[i] - median);  // nearest to the median, first in raster order
                if (e < best)
                {
                    best = e;
                    seed = int(i);
                }
            }
        break;
    }
    if (seed < 0) return 0;

    queue_.clear();
    previous_.clear();
    queue_.push_back(seed);
    previous_.push_back(owner[size_t(seed)]);
    owner[size_t(seed)] = id;
    for (size_t head = 0; head < queue_.size(); ++head)
    {
        const int i = queue_[head];
        const int x = i % W, y = i / W;
        const float z = depth.data[size_t(i)];
        const float limit = relative_step * z;
        const int nb[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
        for (const auto& q : nb)
        {
            if (q[0] < x0 || q[0] >= x1 || q[1] < y0 || q[1] >= y1) continue;
            const size_t j = size_t(q[1]) * W + q[0];
            if (!free(j)) continue;
            const float zj = depth.data[j];
            if (!validDepth(zj) || std::abs(zj - z) >= limit) continue;
            previous_.push_back(owner[j]);
            owner[j] = id;
            queue_.push_back(int(j));
        }
    }
    const double area = double(x1 - x0) * double(y1 - y0);
    if (double(queue_.size()) < min_share * area)
    {
        for (size_t k = 0; k < queue_.size(); ++k) owner[size_t(queue_[k])] = previous_[k];
        return 0;
    }
    return queue_.size();
}

}  // namespace pndt::seg
