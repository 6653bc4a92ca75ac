// The paper's forms of two updates that we do faster or leaner by default:
// free space per ray (NDT-OM) instead of one strongest miss per voxel and
// frame, and h^L over every class (no eviction) instead of the 8 strongest.
// Expected values are counted by hand from the frames.
#include <gtest/gtest.h>
#include <pndt/instance_rules.h>
#include <pndt/panoptic_map.h>

#include <cmath>
#include <vector>

using namespace pndt;

namespace
{
/// 64x48 camera looking along +z at a wall 2 m away, every pixel class `semantic` with S^L `score`.
PanopticFrame wall(uint16_t semantic, float score)
{
    PanopticFrame f;
    f.K = {64, 48, 32.0, 32.0, 31.5, 23.5};
    f.depth.resize(64, 48, 2.0f);
    f.semantic.resize(64, 48, semantic);
    f.semantic_score.resize(64, 48, score);
    f.source = "TEST wall";
    return f;
}

/// The camera sits in the middle of voxel (0, 0, 0): every ray starts there.
Pose centred()
{
    Pose T = Pose::Identity();
    T.translation() = Eigen::Vector3d(0.05, 0.05, 0.05);
    return T;
}

float occupancyAt(const PanopticMap& map, const Eigen::Vector3d& p)
{
    const uint32_t i = map.voxels().find(map.grid().keyOf(p));
    return i == kNoRecord ? 0.f : map.voxels()[i].occ;
}
}  // namespace

TEST(PaperModes, PerRayMissesSumEveryCrossingRayWhereStrongestTakesOne)
{
    for (RayMode rays : {RayMode::PerPixel, RayMode::Merged})
    {
        SCOPED_TRACE(rays == RayMode::PerPixel ? "per-pixel rays" : "merged rays");
        MapOptions o;
        o.ray_mode = rays;
        o.log_odds_min = -1e6f;  // no clamping: the sums show
        PanopticMap strongest(o);
        o.miss_accumulation = MissAccumulation::PerRay;
        PanopticMap per_ray(o);
        const FrameStats a = strongest.integrate(wall(1, 0.9f), centred());
        const FrameStats b = per_ray.integrate(wall(1, 0.9f), centred());
        // Every ray leaves the camera's voxel (the wall is 2 m away): one ray per
        // pixel (3072), or one per hit voxel when merged.
        const uint64_t expected_rays = rays == RayMode::PerPixel ? 64u * 48u : a.hit_voxels;
        ASSERT_EQ(a.rays, expected_rays);
        ASSERT_EQ(b.rays, expected_rays);
        // An empty map has no Gaussians: each crossing costs log_odds_miss.
        EXPECT_FLOAT_EQ(occupancyAt(strongest, {0.05, 0.05, 0.05}), o.log_odds_miss);
        EXPECT_FLOAT_EQ(occupancyAt(per_ray, {0.05, 0.05, 0.05}), float(double(expected_rays) * o.log_odds_miss));
        // The same voxels get misses, only their amounts differ.
        EXPECT_EQ(a.missed_voxels, b.missed_voxels);
        EXPECT_EQ(a.ray_steps, b.ray_steps);
        // Further out, fewer rays share a voxel, but never fewer than one.
        const float mid = occupancyAt(per_ray, {0.05, 0.05, 1.05});
        EXPECT_LE(mid, o.log_odds_miss);
        EXPECT_GT(mid, occupancyAt(per_ray, {0.05, 0.05, 0.05}));
        // The surface itself got its hit, in both.
        EXPECT_FLOAT_EQ(occupancyAt(per_ray, {0.05, 0.05, 2.0}), o.log_odds_hit);
    }
}

TEST(PaperModes, PerRayMissesThroughGaussiansAreAtLeastTheStrongestOne)
{
    // A wall at 2 m seen first, then a wall at 3 m: the rays cross the first
    // wall's Gaussians, whose miss depends on the ray.
    MapOptions o;
    o.ray_mode = RayMode::PerPixel;
    o.log_odds_min = -1e6f;
    PanopticMap strongest(o);
    o.miss_accumulation = MissAccumulation::PerRay;
    PanopticMap per_ray(o);
    PanopticFrame near = wall(1, 0.9f), far = wall(1, 0.9f);
    for (float& d : far.depth.data) d = 3.0f;
    for (PanopticMap* m : {&strongest, &per_ray})
    {
        m->integrate(near, centred());
        m->integrate(far, centred());
    }
    size_t compared = 0, summed_more = 0;
    for (uint32_t i = 0; i < strongest.voxels().size(); ++i)
    {
        const Voxel& v = strongest.voxels()[i];
        if (!strongest.hasGaussian(v)) continue;
        const Eigen::Vector3d p = strongest.pointOf(i);
        if (p.z() > 2.5) continue;  // the first wall
        const float s = v.occ, r = occupancyAt(per_ray, p);
        ++compared;
        // Per ray: the sum of the misses, at least the strongest of them.
        EXPECT_LE(r, s + 1e-5f) << p.transpose();
        summed_more += r < s - 1e-3f;
    }
    EXPECT_GT(compared, 50u);
    EXPECT_GT(summed_more, compared / 2);  // most wall voxels are crossed by several rays
}

TEST(PaperModes, WithoutEvictionHLHoldsEveryClassItWasGiven)
{
    // Ten frames of the same wall, each all one class (1..10, scores rising so
    // that later classes weigh more): every wall voxel sees ten classes, two
    // more than a record holds.
    MapOptions o;
    PanopticMap evicting(o);
    o.semantic_eviction = false;
    PanopticMap dense(o);
    std::vector<float> score(11);
    for (uint16_t c = 1; c <= 10; ++c)
    {
        score[c] = 0.72f + 0.02f * c;
        evicting.integrate(wall(c, score[c]), centred());
        dense.integrate(wall(c, score[c]), centred());
    }
    const ClassSet& classes = o.classes;
    size_t checked = 0;
    for (uint32_t i = 0; i < dense.voxels().size(); ++i)
    {
        const Voxel& v = dense.voxels()[i];
        const LabelRecord* rec = dense.labelsOf(v);
        if (!rec || rec->n_l == 0) continue;
        ++checked;
        ASSERT_EQ(rec->n_l % 10, 0u);
        const uint32_t pixels = rec->n_l / 10;  // the voxel's pixels per frame
        const SemanticSpill* spill = dense.spillOf(v);
        ASSERT_NE(spill, nullptr);
        // The record keeps the eight strongest (classes 3..10), the spill classes 1 and 2.
        EXPECT_EQ(rec->semantic.size(), 8);
        EXPECT_EQ(semanticArgmax(*rec), 10);
        ASSERT_EQ(spill->entries.size(), 2u);
        double sum = 0, stuff = 0;
        for (uint16_t c = 1; c <= 10; ++c)
        {
            const double w = double(pixels) * score[c];
            sum += w;
            if (!classes.isThing(c)) stuff += w;
            const int j = rec->semantic.indexOf(uint8_t(c));
            float got = j >= 0 ? rec->semantic.weight(j) : 0.f;
            for (const auto& e : spill->entries)
                if (e.cls == c) got = e.weight;
            EXPECT_NEAR(got, w, 1e-4 * w) << "class " << c;
        }
        for (const auto& e : spill->entries) EXPECT_LE(e.weight, rec->semantic.weight(7));
        EXPECT_NEAR(semanticMass(*rec, spill), sum, 1e-4 * sum);
        EXPECT_NEAR(stuffMass(*rec, classes, spill), stuff, 1e-4 * sum);
        // The evicting map lost the two weakest classes' mass (wall and floor: stuff).
        const LabelRecord* lossy = evicting.labelsOf(evicting.voxels()[evicting.voxels().find(dense.voxels().key(i))]);
        ASSERT_NE(lossy, nullptr);
        EXPECT_EQ(evicting.spillOf(evicting.voxels()[evicting.voxels().find(dense.voxels().key(i))]), nullptr);
        EXPECT_NEAR(lossy->semantic.sum(), sum - pixels * (score[1] + score[2]), 1e-4 * sum);
    }
    EXPECT_GT(checked, 100u);
    // A wiped voxel loses its spill with its record.
    EXPECT_GT(dense.semanticSpills().size(), 100u);
    dense.clear();
    EXPECT_TRUE(dense.semanticSpills().empty());
}

TEST(PaperModes, ASpilledClassThatOvertakesTakesItsPlaceInTheRecord)
{
    // Nine classes once, then class 1 (spilled, the weakest) again and again:
    // it overtakes the record's smallest entries and moves in.
    MapOptions o;
    o.semantic_eviction = false;
    PanopticMap map(o);
    for (uint16_t c = 1; c <= 9; ++c) map.integrate(wall(c, 0.72f + 0.02f * c), centred());
    for (int k = 0; k < 3; ++k) map.integrate(wall(1, 0.99f), centred());
    size_t checked = 0;
    for (uint32_t i = 0; i < map.voxels().size(); ++i)
    {
        const Voxel& v = map.voxels()[i];
        const LabelRecord* rec = map.labelsOf(v);
        if (!rec || rec->n_l == 0) continue;
        ++checked;
        EXPECT_EQ(semanticArgmax(*rec), 1);  // 0.74 + 3 * 0.99 per pixel: the strongest
        const SemanticSpill* spill = map.spillOf(v);
        ASSERT_NE(spill, nullptr);
        ASSERT_EQ(spill->entries.size(), 1u);
        EXPECT_EQ(spill->entries[0].cls, 2);  // the weakest of the others
        for (int j = 0; j < 8; ++j) EXPECT_GE(rec->semantic.weight(j), spill->entries[0].weight);
    }
    EXPECT_GT(checked, 100u);
}
