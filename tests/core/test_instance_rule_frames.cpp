// The instance rules beyond the paper on hand-drawn frames of a wall: each rule
// does what it says in every combination of options, and a frame that predicts
// no instance inherits nothing from the frame before it.
#include <gtest/gtest.h>
#include <pndt/instance_rules.h>
#include <pndt/panoptic_map.h>

#include <cmath>

#include <vector>

using namespace pndt;

namespace
{
constexpr uint16_t kWall = 1, kChair = 5, kTable = 7;  // NYUv2-40

/// One column range of the image with its class and predicted instance.
struct Stripe
{
    int c0, c1;  ///< columns [c0, c1)
    uint16_t semantic;
    uint32_t instance;
};

/// 64x48 camera at the origin looking along +z at a wall 2 m away (6.25 cm per
/// pixel there: 1.6 pixels per 10 cm voxel). Columns outside every stripe are
/// wall without instance. S^L = 0.95, S^P = 0.9.
PanopticFrame wallWith(const std::vector<Stripe>& stripes)
{
    PanopticFrame f;
    f.K = {64, 48, 32.0, 32.0, 31.5, 23.5};
    f.depth.resize(64, 48, 2.0f);
    f.semantic.resize(64, 48, kWall);
    f.semantic_score.resize(64, 48, 0.95f);
    f.instance.resize(64, 48, 0u);
    f.panoptic_score.resize(64, 48, 0.9f);
    for (const Stripe& s : stripes)
        for (int r = 0; r < 48; ++r)
            for (int c = s.c0; c < s.c1; ++c)
            {
                f.semantic.at(r, c) = s.semantic;
                f.instance.at(r, c) = s.instance;
            }
    f.source = "TEST wall";
    return f;
}

MapOptions paperRules()
{
    MapOptions o;
    o.class_consistent_instances = false;
    o.split_coverage = 0;
    o.fragment_merge_frames = 0;
    o.fragment_absorb_ratio = 0;
    o.label_fill_distance = 0;
    return o;
}

size_t instancesOfClass(const PanopticMap& map, uint16_t semantic)
{
    size_t n = 0;
    for (const MapInstance& mi : map.instances()) n += mi.semantic == semantic;
    return n;
}
}  // namespace

TEST(InstanceRuleFrames, AFrameWithoutPredictionsKeepsNoSplitPixelsOfTheFrameBefore)
{
    MapOptions o;  // defaults: split_coverage 0.7, class-consistent instances
    PanopticMap map(o);
    // Two chairs on the wall, seen three times (splits need two map instances in view).
    const PanopticFrame chairs = wallWith({{0, 16, kChair, 1}, {40, 56, kChair, 2}});
    for (int i = 0; i < 3; ++i) map.integrate(chairs, Pose::Identity());
    ASSERT_EQ(instancesOfClass(map, kChair), 2u);
    // A table prediction swallows the left chair and the wall beside it: split.
    const FrameStats merged = map.integrate(wallWith({{0, 32, kTable, 3}}), Pose::Identity());
    ASSERT_GE(merged.split_predictions, 1u);
    // Then a frame of bare wall with an instance image that predicts nothing:
    // no pixel may take an instance, least of all the chair's from the split.
    const FrameStats bare = map.integrate(wallWith({}), Pose::Identity());
    EXPECT_EQ(bare.predicted_instances, 0u);
    EXPECT_EQ(bare.instance_updates, 0u);
}

TEST(InstanceRuleFrames, FragmentsMergeWithTheOtherRulesOff)
{
    // Two chairs seen apart once, then always as one prediction: after
    // fragment_merge_frames joint frames (and more than twice the apart ones)
    // the newer id joins the older, whatever the other rules say.
    for (const bool class_consistent : {false, true})
        for (const double split : {0.0, 0.5})
        {
            MapOptions o = paperRules();
            o.fragment_merge_frames = 3;
            o.class_consistent_instances = class_consistent;
            o.split_coverage = split;
            PanopticMap map(o);
            map.integrate(wallWith({{0, 16, kChair, 1}, {32, 48, kChair, 2}}), Pose::Identity());
            map.integrate(wallWith({{0, 16, kChair, 1}, {32, 48, kChair, 2}}), Pose::Identity());
            ASSERT_EQ(instancesOfClass(map, kChair), 2u) << class_consistent << " " << split;
            uint64_t merged = 0;
            for (int i = 0; i < 4; ++i)
                merged += map.integrate(wallWith({{0, 48, kChair, 7}}), Pose::Identity()).merged_fragments;
            EXPECT_EQ(merged, 1u) << "class_consistent " << class_consistent << ", split " << split;
        }
}

TEST(InstanceRuleFrames, FrameTotalsCountSplitsAndMergedFragments)
{
    // FrameStats::operator+= once dropped these two counters: a run's totals
    // said no prediction was ever split and no fragment merged.
    MapOptions o;
    o.fragment_merge_frames = 3;
    PanopticMap map(o);
    FrameStats totals;
    uint64_t splits = 0, merges = 0;
    const auto frame = [&](const PanopticFrame& f) {
        const FrameStats st = map.integrate(f, Pose::Identity());
        splits += st.split_predictions;
        merges += st.merged_fragments;
        totals += st;
    };
    for (int i = 0; i < 3; ++i) frame(wallWith({{0, 16, kChair, 1}, {40, 56, kChair, 2}}));
    frame(wallWith({{0, 32, kTable, 3}}));
    for (int i = 0; i < 8; ++i) frame(wallWith({{0, 56, kChair, 7}}));
    ASSERT_GE(splits, 1u);
    ASSERT_GE(merges, 1u);
    EXPECT_EQ(totals.split_predictions, splits);
    EXPECT_EQ(totals.merged_fragments, merges);
}

TEST(InstanceRuleFrames, NoFragmentMergeWhenTheRuleIsOff)
{
    PanopticMap map(paperRules());
    map.integrate(wallWith({{0, 16, kChair, 1}, {32, 48, kChair, 2}}), Pose::Identity());
    map.integrate(wallWith({{0, 16, kChair, 1}, {32, 48, kChair, 2}}), Pose::Identity());
    uint64_t merged = 0;
    for (int i = 0; i < 4; ++i) merged += map.integrate(wallWith({{0, 48, kChair, 7}}), Pose::Identity()).merged_fragments;
    EXPECT_EQ(merged, 0u);
}

TEST(InstanceRuleFrames, EquationNineSumsThePThingVoxelsOrEveryTopVoxel)
{
    // One prediction covers a chair (columns 0-15) and a table beside it
    // (16-47) once; afterwards the table is seen without instance, so its voxels
    // keep instance z at the top of h^Z but fail pthing (n^Z/n^L = 1/9 < 0.25).
    // The instance's class: chair from its pthing voxels only; table (twice the
    // chair's mass) when every voxel whose top entry is z votes (the paper).
    for (const InstanceClassVoxels mode : {InstanceClassVoxels::PanopticThing, InstanceClassVoxels::TopInstance})
    {
        MapOptions o = paperRules();
        o.instance_class_voxels = mode;
        PanopticMap map(o);
        map.integrate(wallWith({{0, 16, kChair, 1}, {16, 48, kTable, 1}}), Pose::Identity());
        for (int i = 0; i < 8; ++i) map.integrate(wallWith({{0, 16, kChair, 1}, {16, 48, kTable, 0}}), Pose::Identity());
        const auto instances = map.instances();
        ASSERT_EQ(instances.size(), 1u);
        EXPECT_EQ(instances[0].semantic, mode == InstanceClassVoxels::PanopticThing ? kChair : kTable);
        // Either way only the chair's voxels carry the instance.
        EXPECT_LT(instances[0].bbox_max.x(), -0.9);
    }
}

TEST(InstanceRuleFrames, AFreedVoxelKeepsItsLabelsUnlessResetIsOn)
{
    // A labelled wall at 2 m, then the wall moves to 3 m: the rays through the
    // old wall clear it. reset_freed_voxels wipes its shape and labels (default);
    // off, it keeps them and only its occupancy falls.
    for (const bool reset : {true, false})
    {
        MapOptions o;
        o.reset_freed_voxels = reset;
        o.ray_mode = RayMode::PerPixel;  // every pixel's ray crosses the old wall
        PanopticMap map(o);
        for (int i = 0; i < 3; ++i) map.integrate(wallWith({{0, 16, kChair, 1}}), Pose::Identity());
        PanopticFrame far = wallWith({});
        far.depth.resize(64, 48, 3.0f);
        for (int i = 0; i < 20; ++i) map.integrate(far, Pose::Identity());
        const uint32_t old_wall = map.voxels().find(map.grid().keyOf({0.01, 0.01, 2.0}));
        ASSERT_NE(old_wall, kNoRecord);
        const Voxel& v = map.voxels()[old_wall];
        EXPECT_LT(v.occ, 0.f) << "reset " << reset;
        const LabelRecord* rec = map.labelsOf(v);  // wiped records stay allocated for reuse
        ASSERT_NE(rec, nullptr);
        EXPECT_EQ(rec->semantic.empty(), reset);
        if (!reset)
        {
            EXPECT_EQ(rec->semantic.top(), kWall);
        }
        EXPECT_EQ(map.shapeOf(v).n == 0, reset);
    }
}

TEST(InstanceRuleFrames, VoidPixelsFillTheVoidBinOnlyWhenAsked)
{
    // Columns 0-15 void with S^L = 0.95 > theta_l.
    for (const bool void_bin : {false, true})
    {
        MapOptions o;
        o.void_bin = void_bin;
        PanopticMap map(o);
        map.integrate(wallWith({{0, 16, 0, 0}}), Pose::Identity());
        const uint32_t vi = map.voxels().find(map.grid().keyOf({-1.5, 0.01, 2.0}));
        ASSERT_NE(vi, kNoRecord);
        const LabelRecord* rec = map.labelsOf(map.voxels()[vi]);
        ASSERT_EQ(rec != nullptr, void_bin);
        if (void_bin)
        {
            EXPECT_EQ(rec->semantic.top(), kVoidBin);
            EXPECT_EQ(map.semanticLabel(vi), 0);  // reads as void
            EXPECT_EQ(map.panopticLabel(vi), PanopticLabel{});
        }
    }
}

TEST(InstanceRuleFrames, OccupiedThresholdDecidesWhatIsOccupied)
{
    // One hit gives +0.85: occupied at threshold 0, not at threshold 1.
    for (const float threshold : {0.f, 1.f})
    {
        MapOptions o;
        o.occupied_threshold = threshold;
        PanopticMap map(o);
        map.integrate(wallWith({}), Pose::Identity());
        const uint32_t wall = map.voxels().find(map.grid().keyOf({0.01, 0.01, 2.0}));
        ASSERT_NE(wall, kNoRecord);
        EXPECT_EQ(map.isOccupied(map.voxels()[wall]), threshold == 0.f);
    }
}

TEST(InstanceRuleFrames, InstanceConfidenceGrowsWithFramesAndFallsWithRivals)
{
    // Hand-computed: confidence = weight share x (1 - exp(-frames / 3)).
    EXPECT_DOUBLE_EQ(instanceConfidence(1.0, 0), 0.0);
    EXPECT_DOUBLE_EQ(instanceConfidence(1.0, 3), 1.0 - std::exp(-1.0));
    EXPECT_DOUBLE_EQ(instanceConfidence(0.5, 3), 0.5 * (1.0 - std::exp(-1.0)));

    // A chair seen in 5 frames alone, another seen twice: frames count, shares are 1.
    PanopticMap map(paperRules());
    const PanopticFrame both = wallWith({{0, 16, kChair, 1}, {40, 56, kChair, 2}});
    const PanopticFrame left = wallWith({{0, 16, kChair, 1}});
    for (int i = 0; i < 2; ++i) map.integrate(both, Pose::Identity());
    for (int i = 0; i < 3; ++i) map.integrate(left, Pose::Identity());
    const auto inst = map.instances();
    ASSERT_EQ(inst.size(), 2u);
    const MapInstance& a = inst[0].centroid.x() < inst[1].centroid.x() ? inst[0] : inst[1];
    const MapInstance& b = &a == &inst[0] ? inst[1] : inst[0];
    EXPECT_EQ(a.frames_seen, 5u);
    EXPECT_EQ(b.frames_seen, 2u);
    EXPECT_FLOAT_EQ(a.weight_share, 1.f);
    EXPECT_FLOAT_EQ(b.weight_share, 1.f);
    EXPECT_DOUBLE_EQ(a.confidence, instanceConfidence(1.0, 5));
    EXPECT_GT(a.confidence, b.confidence);
    // Renaming keeps the counts with the ids; merging two keeps the larger.
    map.renameInstances([&](uint32_t id) { return id == b.id ? a.id : id; });
    ASSERT_EQ(map.instanceFrames().size(), 1u);
    EXPECT_EQ(map.instanceFrames()[0], std::make_pair(a.id, 5u));
}

TEST(InstanceRuleFrames, IdsNoRecordHoldsAreForgottenWhenTheCounterPassesASweep)
{
    PanopticMap map(paperRules());
    const uint32_t sweep = PanopticMap::kDeadInstanceSweep;
    const PanopticFrame left = wallWith({{0, 16, kChair, 1}});
    for (int i = 0; i < 2; ++i) map.integrate(left, Pose::Identity());
    ASSERT_EQ(map.nextInstanceId(), 2u);
    // Ids 5 and sweep - 100 held by no record (as after evictions or merges),
    // with frames seen and fragment evidence, and the counter two below a sweep.
    map.reserveInstanceIds(sweep - 2);
    map.restoreInstanceFrames({{1, 2}, {5, 3}, {sweep - 100, 1}});
    map.restorePairEvidence({{1, 5, 2, 0}, {5, sweep - 100, 1, 1}});
    // A new chair (id sweep - 2): the counter stays below the sweep, nothing is forgotten.
    const PanopticFrame two = wallWith({{0, 16, kChair, 1}, {40, 56, kChair, 2}});
    FrameStats st = map.integrate(two, Pose::Identity());
    ASSERT_EQ(st.new_instances, 1u);
    EXPECT_EQ(map.instanceFrames(), (std::vector<std::pair<uint32_t, uint32_t>>{
                                        {1, 3}, {5, 3}, {sweep - 100, 1}, {sweep - 2, 1}}));
    EXPECT_EQ(map.pairEvidence().size(), 2u);
    // A third chair (id sweep - 1, counter to sweep): the dead ids go, the live keep their counts.
    st = map.integrate(wallWith({{0, 16, kChair, 1}, {24, 32, kChair, 3}, {40, 56, kChair, 2}}), Pose::Identity());
    ASSERT_EQ(st.new_instances, 1u);
    ASSERT_EQ(st.matched_instances, 2u);
    ASSERT_EQ(map.nextInstanceId(), sweep);
    EXPECT_EQ(map.instanceFrames(),
              (std::vector<std::pair<uint32_t, uint32_t>>{{1, 4}, {sweep - 2, 2}, {sweep - 1, 1}}));
    EXPECT_TRUE(map.pairEvidence().empty());
    EXPECT_EQ(map.instances().size(), 3u);
}

TEST(InstanceRuleFrames, IouMatchingOnHandDrawnMasks)
{
    // A wall at 2 m, chairs drawn as column stripes; theta_M / theta_N = 0.5 / 0.05
    // leave room for the voxels' footprints (1.6 px per voxel) around the
    // hand-computed IoUs.
    MapOptions o = paperRules();
    o.theta_m = 0.5;
    o.theta_n = 0.05;
    PanopticMap map(o);
    // Frame 1: one chair, columns 0..31: a new instance, id 1.
    FrameStats st = map.integrate(wallWith({{0, 32, kChair, 7}}), Pose::Identity());
    EXPECT_EQ(st.new_instances, 1u);
    EXPECT_EQ(map.nextInstanceId(), 2u);
    // Frame 2: columns 0..35 (IoU with id 1: 32 / 36 = 0.89) matches it; columns
    // 44..63 (IoU 0) is new: id 2, the next id.
    st = map.integrate(wallWith({{0, 36, kChair, 3}, {44, 64, kChair, 4}}), Pose::Identity());
    EXPECT_EQ(st.matched_instances, 1u);
    EXPECT_EQ(st.new_instances, 1u);
    EXPECT_EQ(map.nextInstanceId(), 3u);
    auto inst = map.instances();
    ASSERT_EQ(inst.size(), 2u);
    EXPECT_EQ(inst[0].id, 1u);
    EXPECT_LT(inst[0].centroid.x(), 0.0);  // the left chair kept id 1
    EXPECT_EQ(inst[1].id, 2u);
    EXPECT_GT(inst[1].centroid.x(), 0.0);
    // Frame 3: columns 16..63 overlaps both (IoU 20 / 64 = 0.31 with id 1, 20 / 48
    // = 0.42 with id 2): ambiguous, no instance update and no id used.
    st = map.integrate(wallWith({{16, 64, kChair, 5}}), Pose::Identity());
    EXPECT_EQ(st.ambiguous_instances, 1u);
    EXPECT_EQ(st.matched_instances + st.new_instances, 0u);
    EXPECT_EQ(st.instance_updates, 0u);
    EXPECT_EQ(map.nextInstanceId(), 3u);
}

TEST(InstanceRuleFrames, LabelAtTakesTheGaussianNearestInMahalanobisDistance)
{
    // Two stacked voxels with hand-set Gaussians (11 samples each, so variances are
    // scatter / 10, plus the minimum variance (0.05 x 0.1 m)^2 = 2.5e-5):
    // A in z [2.0, 2.1): mean z 2.09, variance_z 2.5e-5 (sigma 5 mm), class wall;
    // B in z [2.1, 2.2): mean z 2.11, variance_z 1e-4 (sigma 1 cm), class picture.
    MapOptions o;
    PanopticMap map(o);
    const auto shape = [](double z, double m2_zz) {
        NdtShape s;
        s.n = 11;
        s.mean[0] = s.mean[1] = 0.05f;
        s.mean[2] = float(z);
        s.m2[0] = s.m2[3] = 0.01f;  // x, y: variance 1e-3
        s.m2[5] = float(m2_zz);
        return s;
    };
    const Eigen::Vector3d pa(0.05, 0.05, 2.09), pb(0.05, 0.05, 2.11);
    std::vector<uint64_t> keys = {map.grid().keyOf(pa).packed(), map.grid().keyOf(pb).packed()};
    ASSERT_NE(keys[0], keys[1]);
    std::vector<Voxel> voxels = {{1.f, 0}, {1.f, 1}};
    std::vector<SurfaceRecord> surfaces(2);
    surfaces[0].shape = shape(2.09, 0.0);
    surfaces[1].shape = shape(2.11, 7.5e-4);
    surfaces[0].labels = 0;
    surfaces[1].labels = 1;
    std::vector<LabelRecord> labels(2);
    labels[0].semantic.add(kWall, 5.f);
    labels[1].semantic.add(11, 5.f);  // picture
    labels[0].n_l = labels[1].n_l = 5;
    map.restore(keys, voxels, surfaces, labels, {}, 1);

    // z = 2.099 lies in A, 9 mm from A's mean and 11 mm from B's: in Mahalanobis
    // terms 0.009^2 / 2.5e-5 = 3.24 against 0.011^2 / 1e-4 = 1.21, so B.
    const double a_mean = double(2.09f), b_mean = double(2.11f);  // the stored floats
    PointLabel l = map.labelAt({0.05, 0.05, 2.099});
    ASSERT_TRUE(l.found);
    EXPECT_EQ(l.semantic, 11);
    EXPECT_NEAR(l.mahalanobis_sq, (b_mean - 2.099) * (b_mean - 2.099) / 1e-4, 1e-3);
    // z = 2.093: 0.003^2 / 2.5e-5 = 0.36 against 0.017^2 / 1e-4 = 2.89: A.
    l = map.labelAt({0.05, 0.05, 2.093});
    ASSERT_TRUE(l.found);
    EXPECT_EQ(l.semantic, kWall);
    EXPECT_NEAR(l.mahalanobis_sq, (2.093 - a_mean) * (2.093 - a_mean) / 2.5e-5, 1e-3);
    // Far from both (and their neighbourhoods): void.
    EXPECT_FALSE(map.labelAt({0.05, 0.05, 2.5}).found);
}
