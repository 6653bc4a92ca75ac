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
                           double min_share, std::vector<uint32_t>& owner)
{
    const int W = depth.width, H = depth.height;
    const int x0 = std::clamp(int(std::floor(b.x0)), 0, W), x1 = std::clamp(int(std::ceil(b.x1)), 0, W);
    const int y0 = std::clamp(int(std::floor(b.y0)), 0, H), y1 = std::clamp(int(std::ceil(b.y1)), 0, H);
    if (x1 <= x0 || y1 <= y0) return 0;

    // Seed: the free valid pixel of the central third whose depth is the window's median.
    const int cw = std::max(1, (x1 - x0) / 3), ch = std::max(1, (y1 - y0) / 3);
    const int cx0 = x0 + (x1 - x0 - cw) / 2, cy0 = y0 + (y1 - y0 - ch) / 2;
    window_.clear();
    for (int y = cy0; y < cy0 + ch; ++y)
        for (int x = cx0; x < cx0 + cw; ++x)
            if (validDepth(depth.at(y, x)) && owner[size_t(y) * W + x] == 0) window_.push_back(depth.at(y, x));
    if (window_.empty()) return 0;
    std::nth_element(window_.begin(), window_.begin() + long(window_.size() / 2), window_.end());
    const float median = window_[window_.size() / 2];
    int seed = -1;
    float best = 1e30f;
    for (int y = cy0; y < cy0 + ch; ++y)
        for (int x = cx0; x < cx0 + cw; ++x)
        {
            const size_t i = size_t(y) * W + x;
            if (owner[i] != 0 || !validDepth(depth.data[i])) continue;
            // Nearest to the median, then nearest to the box centre (deterministic).
            const float e = std::abs(depth.data[i] - median);
            if (e < best)
            {
                best = e;
                seed = int(i);
            }
        }
    if (seed < 0) return 0;

    queue_.clear();
    queue_.push_back(seed);
    owner[size_t(seed)] = id;
    for (size_t head = 0; head < queue_.size(); ++head)
    {
        const int i = queue_[head];
        const int x = i % W, y = i / W;
        const float z = depth.data[size_t(i)];
        const float limit = float(depth_step) * z;
        const int nb[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
        for (const auto& q : nb)
        {
            if (q[0] < x0 || q[0] >= x1 || q[1] < y0 || q[1] >= y1) continue;
            const size_t j = size_t(q[1]) * W + q[0];
            if (owner[j] != 0) continue;
            const float zj = depth.data[j];
            if (!validDepth(zj) || std::abs(zj - z) >= limit) continue;
            owner[j] = id;
            queue_.push_back(int(j));
        }
    }
    const double area = double(x1 - x0) * double(y1 - y0);
    if (double(queue_.size()) < min_share * area)
    {
        for (int i : queue_) owner[size_t(i)] = 0;
        return 0;
    }
    return queue_.size();
}

}  // namespace pndt::seg
