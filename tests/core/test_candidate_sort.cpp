// Instance matching's candidate sort: the order std::sort gives, for the sizes
// and id ranges a frame has (the radix passes start at 64 candidates).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

#include "candidate_sort.h"

namespace pndt::test
{
TEST(CandidateSort, HandCheckedOrder)
{
    // 70 candidates (radix path): instance 300 before 7 * 256 + 1, voxels ascending within each.
    std::vector<MaskCandidate> v, tmp;
    for (uint32_t i = 0; i < 35; ++i)
    {
        v.push_back({7 * 256 + 1, 1000 - 3 * i, i});
        v.push_back({300, 70000 + 5 * i, 100 + i});
    }
    sortCandidates(v, tmp);
    ASSERT_EQ(v.size(), 70u);
    EXPECT_EQ(v[0].first, 300u);
    EXPECT_EQ(v[0].second, 70000u);
    EXPECT_EQ(v[0].thing, 100u);
    EXPECT_EQ(v[34].second, 70000u + 5 * 34);
    EXPECT_EQ(v[35].first, 7u * 256 + 1);
    EXPECT_EQ(v[35].second, 1000u - 3 * 34);  // the smallest voxel of instance 1793
    EXPECT_EQ(v[35].thing, 34u);
    EXPECT_EQ(v[69].second, 1000u);
}

TEST(CandidateSort, SameOrderAsStdSort)
{
    std::mt19937 rng(5);
    std::vector<MaskCandidate> tmp;
    for (const size_t n : {0u, 1u, 2u, 63u, 64u, 65u, 1000u, 6000u})
        for (const uint32_t instance_range : {1u, 40u, 70000u, 0x7fffffffu})
            for (const uint32_t voxel_range : {1u << 8, 1u << 16, 1u << 26})
            {
                // Unique (instance, voxel) pairs, as the map gives them (no more than there are).
                if (uint64_t(instance_range) * voxel_range < 2 * n) continue;
                std::set<std::pair<uint32_t, uint32_t>> seen;
                std::vector<MaskCandidate> v;
                while (v.size() < n)
                {
                    const uint32_t z = 1 + uint32_t(rng() % instance_range), vox = uint32_t(rng() % voxel_range);
                    if (seen.insert({z, vox}).second) v.push_back({z, vox, uint32_t(v.size())});
                }
                std::vector<MaskCandidate> want = v;
                std::sort(want.begin(), want.end());
                sortCandidates(v, tmp);
                ASSERT_EQ(v.size(), want.size());
                for (size_t i = 0; i < n; ++i)
                {
                    ASSERT_EQ(v[i].first, want[i].first) << n << " " << instance_range << " " << voxel_range << " " << i;
                    ASSERT_EQ(v[i].second, want[i].second) << n << " " << i;
                    ASSERT_EQ(v[i].thing, want[i].thing) << n << " " << i;
                }
            }
}

}  // namespace pndt::test
