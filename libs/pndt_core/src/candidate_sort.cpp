#include "candidate_sort.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace pndt
{
namespace
{
/// One stable counting pass on the byte of key(c) at `shift`: src into dst.
/// Returns false (and leaves dst alone) when every candidate has the same byte.
template <typename Key>
bool countingPass(const MaskCandidate* src, MaskCandidate* dst, size_t n, int shift, Key key)
{
    uint32_t start[256] = {0};
    for (size_t i = 0; i < n; ++i) ++start[(key(src[i]) >> shift) & 255u];
    if (start[(key(src[0]) >> shift) & 255u] == n) return false;
    uint32_t sum = 0;
    for (uint32_t& s : start) sum += std::exchange(s, sum);
    for (size_t i = 0; i < n; ++i) dst[start[(key(src[i]) >> shift) & 255u]++] = src[i];
    return true;
}
}  // namespace

void sortCandidates(std::vector<MaskCandidate>& v, std::vector<MaskCandidate>& tmp)
{
    const size_t n = v.size();
    if (n < 64)  // a few passes over 256 buckets cost more
    {
        std::sort(v.begin(), v.end());
        return;
    }
    uint32_t first_bits = 0, second_bits = 0;
    for (const MaskCandidate& c : v)
    {
        first_bits |= c.first;
        second_bits |= c.second;
    }
    tmp.resize(n);
    MaskCandidate *src = v.data(), *dst = tmp.data();
    const auto voxel = [](const MaskCandidate& c) { return c.second; };
    const auto instance = [](const MaskCandidate& c) { return c.first; };
    for (int shift = 0; shift < 32 && (second_bits >> shift) != 0; shift += 8)
        if (countingPass(src, dst, n, shift, voxel)) std::swap(src, dst);
    for (int shift = 0; shift < 32 && (first_bits >> shift) != 0; shift += 8)
        if (countingPass(src, dst, n, shift, instance)) std::swap(src, dst);
    if (src != v.data()) std::copy(src, src + n, v.data());
}

}  // namespace pndt
