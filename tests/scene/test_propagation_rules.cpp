// Panoptic label propagation (paper step 7) on a hand-built map state.
#include <gtest/gtest.h>
#include <pndt/panoptic_map.h>

using namespace pndt;

namespace
{
constexpr uint8_t kChair = 5, kSofa = 6, kWall = 1, kRug = 20;

/// One occupied voxel at x = i with the given semantic entries, n^L, n^Z and
/// instance entries.
struct VoxelSpec
{
    std::vector<std::pair<uint8_t, float>> semantic;
    uint32_t n_l, n_z;
    std::vector<std::pair<uint32_t, float>> instances;
};

/// `at`: voxel keys along x (default: 5 apart, so no voxel touches another).
PanopticMap build(const std::vector<VoxelSpec>& specs, uint32_t next_id, MapOptions options = {},
                  std::vector<int32_t> at = {})
{
    std::vector<uint64_t> keys;
    std::vector<Voxel> voxels;
    std::vector<SurfaceRecord> surfaces;
    std::vector<LabelRecord> labels;
    std::vector<InstanceRecord> inst;
    for (size_t i = 0; i < specs.size(); ++i)
    {
        keys.push_back(VoxelKey{at.empty() ? int32_t(i) * 5 : at[i], 0, 0}.packed());
        Voxel v;
        v.occ = 2.f;
        v.surface = uint32_t(surfaces.size());
        voxels.push_back(v);
        SurfaceRecord s;
        s.shape.n = 10;
        s.labels = uint32_t(labels.size());
        surfaces.push_back(s);
        LabelRecord r;
        for (const auto& [c, w] : specs[i].semantic) r.semantic.add(c, w);
        r.n_l = specs[i].n_l;
        if (!specs[i].instances.empty())
        {
            r.instances = uint32_t(inst.size());
            inst.emplace_back();
            for (const auto& [z, w] : specs[i].instances) inst.back().hist.add(z, w);
            inst.back().n_z = specs[i].n_z;
        }
        labels.push_back(r);
    }
    PanopticMap map(options);
    map.restore(keys, voxels, surfaces, labels, inst, next_id);
    return map;
}
}  // namespace

TEST(Propagation, InstanceTakesTheThingClassWithTheLargestSumOverItsVoxels)
{
    // Instance 7: voxel 0 says chair (5), voxels 1-2 say sofa (3 each): sums chair 5,
    // sofa 6 -> every voxel of 7 is a sofa, even voxel 0 whose own argmax is chair.
    // Voxel 3 is instance 8, all chair. Voxel 4 has too few instance updates
    // (n^Z/n^L = 0.2 < 0.25): <argmax h^L, 0>. Voxel 5 is wall: stuff.
    const PanopticMap map = build({{{{kChair, 5.f}}, 10, 10, {{7, 4.f}}},
                                   {{{kSofa, 3.f}}, 10, 10, {{7, 4.f}}},
                                   {{{kSofa, 3.f}, {kChair, 0.5f}}, 10, 10, {{7, 4.f}}},
                                   {{{kChair, 2.f}}, 10, 10, {{8, 1.f}}},
                                   {{{kChair, 2.f}}, 10, 2, {{7, 1.f}}},
                                   {{{kWall, 9.f}}, 10, 0, {}}},
                                  9);
    // sums for 7: chair 5 + 0.5 = 5.5, sofa 6 -> sofa
    EXPECT_EQ(map.panopticLabel(0), (PanopticLabel{kSofa, 7}));
    EXPECT_EQ(map.panopticLabel(1), (PanopticLabel{kSofa, 7}));
    EXPECT_EQ(map.panopticLabel(2), (PanopticLabel{kSofa, 7}));
    EXPECT_EQ(map.panopticLabel(3), (PanopticLabel{kChair, 8}));
    EXPECT_EQ(map.panopticLabel(4), (PanopticLabel{kChair, 0}));
    EXPECT_EQ(map.panopticLabel(5), (PanopticLabel{kWall, 0}));
    EXPECT_EQ(map.semanticLabel(0), kChair);  // the plain semantic output is not propagated
    const auto inst = map.instances();
    ASSERT_EQ(inst.size(), 2u);
    EXPECT_EQ(inst[0].id, 7u);
    EXPECT_EQ(inst[0].semantic, kSofa);
    EXPECT_EQ(inst[0].voxel_count, 3u);
    EXPECT_EQ(inst[1].id, 8u);
}

TEST(Propagation, PThingFlipsAtThetaO)
{
    // n^Z/n^L exactly 0.25 takes the instance; one update less does not.
    const PanopticMap at = build({{{{kChair, 2.f}}, 100, 25, {{3, 1.f}}}}, 4);
    const PanopticMap below = build({{{{kChair, 2.f}}, 100, 24, {{3, 1.f}}}}, 4);
    EXPECT_EQ(at.panopticLabel(0), (PanopticLabel{kChair, 3}));
    EXPECT_EQ(below.panopticLabel(0), (PanopticLabel{kChair, 0}));
}

TEST(Propagation, StuffDominatedVoxelNeverTakesAnInstance)
{
    // 0.9 of the semantic mass is wall: not a thing, whatever its instance counts.
    const PanopticMap map = build({{{{kWall, 9.f}, {kChair, 1.f}}, 10, 10, {{5, 3.f}}}}, 6);
    EXPECT_EQ(map.panopticLabel(0), (PanopticLabel{kWall, 0}));
    EXPECT_TRUE(map.instances().empty());
}

TEST(Propagation, VoxelOfAnotherClassMovesToItsStrongestInstanceOfItsClass)
{
    // Instance 7 holds two chair voxels and one rug voxel (an early merged
    // prediction); the rug voxel also holds instance 9 (weight 3 of 8: in its top
    // z), which voxel 3, a rug, takes. Voxel 4 is a rug whose only other entry
    // (weight 0.5 of 10.5) is outside its top z: it stays with 7.
    const std::vector<VoxelSpec> specs = {{{{kChair, 5.f}}, 10, 10, {{7, 4.f}}},
                                          {{{kChair, 5.f}}, 10, 10, {{7, 4.f}}},
                                          {{{kRug, 4.f}}, 10, 10, {{7, 5.f}, {9, 3.f}}},
                                          {{{kRug, 4.f}}, 10, 10, {{9, 4.f}}},
                                          {{{kRug, 1.f}}, 10, 10, {{7, 10.f}, {9, 0.5f}}}};
    const PanopticMap map = build(specs, 10);
    EXPECT_EQ(map.panopticLabel(0), (PanopticLabel{kChair, 7}));
    EXPECT_EQ(map.panopticLabel(2), (PanopticLabel{kRug, 9}));
    EXPECT_EQ(map.panopticLabel(3), (PanopticLabel{kRug, 9}));
    EXPECT_EQ(map.panopticLabel(4), (PanopticLabel{kChair, 7}));
    const auto inst = map.instances();
    ASSERT_EQ(inst.size(), 2u);
    EXPECT_EQ(inst[0].voxel_count, 3u);  // 7: voxels 0, 1, 4
    EXPECT_EQ(inst[1].voxel_count, 2u);  // 9: voxels 2, 3

    // The paper's rule: the top entry, whatever the voxel's own class.
    MapOptions paper;
    paper.class_consistent_instances = false;
    const PanopticMap p = build(specs, 10, paper);
    EXPECT_EQ(p.panopticLabel(2), (PanopticLabel{kChair, 7}));
}

namespace
{
const VoxelSpec kChairVoxel7 = {{{kChair, 5.f}}, 10, 10, {{7, 4.f}}};
const VoxelSpec kUnlabelled = {{}, 0, 0, {}};  // every view of it was below theta_L
const VoxelSpec kWallVoxel = {{{kWall, 5.f}}, 10, 0, {}};
}  // namespace

TEST(Propagation, UnlabelledSurfaceTakesItsNeighboursLabelUpToTheFillDistance)
{
    // x = 0: chair of instance 7; x = 1, 2, 3 unlabelled. 0.2 m at 0.1 m voxels
    // is two steps: x = 1 (from 0), then x = 2 (from 1); x = 3 stays void.
    // x = 10 chair 7 and x = 12 wall, x = 11 between them: one vote each, the
    // tie goes to the smaller <class, instance>: wall (1) before chair (5).
    MapOptions o;
    o.voxel_size = 0.1;
    o.label_fill_distance = 0.2;
    o.fragment_absorb_ratio = 0;
    const std::vector<VoxelSpec> specs = {kChairVoxel7, kUnlabelled, kUnlabelled, kUnlabelled,
                                          kChairVoxel7, kUnlabelled, kWallVoxel};
    const std::vector<int32_t> at = {0, 1, 2, 3, 10, 11, 12};
    const PanopticMap map = build(specs, 8, o, at);
    EXPECT_EQ(map.panopticLabel(1), (PanopticLabel{kChair, 7}));
    EXPECT_EQ(map.panopticLabel(2), (PanopticLabel{kChair, 7}));
    EXPECT_EQ(map.panopticLabel(3), PanopticLabel{});
    EXPECT_EQ(map.panopticLabel(5), (PanopticLabel{kWall, 0}));
    EXPECT_EQ(map.semanticLabel(1), 0);  // the semantic output keeps what was observed
    const auto inst = map.instances();
    ASSERT_EQ(inst.size(), 1u);
    EXPECT_EQ(inst[0].voxel_count, 4u);  // x = 0, 1, 2, 10

    // Off: the paper's void.
    o.label_fill_distance = 0;
    const PanopticMap paper = build(specs, 8, o, at);
    EXPECT_EQ(paper.panopticLabel(1), PanopticLabel{});
    EXPECT_EQ(paper.instances()[0].voxel_count, 2u);
}

TEST(Propagation, SmallFragmentJoinsTheTouchingInstanceOfItsClass)
{
    // Instance 7: ten chair voxels x = 0..9. Instance 8: one chair voxel at x = 10,
    // touching 7, 1 <= 0.15 * 10: joins 7. Instance 9: one chair voxel at x = 20,
    // touching nothing: stays. Instance 11: a sofa voxel at x = -1, touching 7
    // but of another class: stays.
    MapOptions o;
    o.voxel_size = 0.1;
    o.label_fill_distance = 0;
    o.fragment_absorb_ratio = 0.15;
    std::vector<VoxelSpec> specs(10, kChairVoxel7);
    std::vector<int32_t> at = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
    specs.push_back({{{kChair, 5.f}}, 10, 10, {{8, 4.f}}});
    at.push_back(10);
    specs.push_back({{{kChair, 5.f}}, 10, 10, {{9, 4.f}}});
    at.push_back(20);
    specs.push_back({{{kSofa, 5.f}}, 10, 10, {{11, 4.f}}});
    at.push_back(-1);
    const PanopticMap map = build(specs, 12, o, at);
    EXPECT_EQ(map.panopticLabel(10), (PanopticLabel{kChair, 7}));
    EXPECT_EQ(map.panopticLabel(11), (PanopticLabel{kChair, 9}));
    EXPECT_EQ(map.panopticLabel(12), (PanopticLabel{kSofa, 11}));
    const auto inst = map.instances();
    ASSERT_EQ(inst.size(), 3u);
    EXPECT_EQ(inst[0].id, 7u);
    EXPECT_EQ(inst[0].voxel_count, 11u);

    // Two voxels are more than 0.15 of ten: a neighbour, not a fragment.
    specs.push_back({{{kChair, 5.f}}, 10, 10, {{8, 4.f}}});
    at.push_back(-2);  // instance 8 now has two voxels
    const PanopticMap two = build(specs, 12, o, at);
    EXPECT_EQ(two.panopticLabel(10), (PanopticLabel{kChair, 8}));

    // At the default 0.35 they are: 2 <= 0.35 * 10.
    o.fragment_absorb_ratio = MapOptions{}.fragment_absorb_ratio;
    ASSERT_EQ(o.fragment_absorb_ratio, 0.35);
    EXPECT_EQ(build(specs, 12, o, at).panopticLabel(10), (PanopticLabel{kChair, 7}));

    // Off: the paper keeps every instance.
    o.fragment_absorb_ratio = 0;
    specs.pop_back();
    at.pop_back();
    EXPECT_EQ(build(specs, 12, o, at).panopticLabel(10), (PanopticLabel{kChair, 8}));
}
