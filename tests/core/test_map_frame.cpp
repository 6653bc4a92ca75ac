// PanopticMap on hand-made frames: counts, hit/miss log-odds, bad input.
#include <gtest/gtest.h>
#include <pndt/instance_rules.h>
#include <pndt/panoptic_map.h>
#include <pndt/ray_walk.h>

#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <set>

using namespace pndt;

namespace
{
/// 64x48 camera at the origin looking along world +z at a wall at depth `z`.
PanopticFrame wallFrame(float z)
{
    PanopticFrame f;
    f.K = {64, 48, 32.0, 32.0, 31.5, 23.5};
    f.depth.resize(64, 48, z);
    f.source = "TEST @ 1.0";
    return f;
}

/// A map of one voxel per record of `records` (its instance ids and weights,
/// class 5), along x, with the id counter at `next_id`.
void restoreInstanceRecords(PanopticMap& map, const std::vector<std::vector<std::pair<uint32_t, float>>>& records,
                            uint32_t next_id)
{
    const size_t n = records.size();
    std::vector<InstanceRecord> inst(n);
    std::vector<LabelRecord> labels(n);
    std::vector<Voxel> voxels(n);
    std::vector<SurfaceRecord> surfaces(n);
    std::vector<uint64_t> keys;
    for (uint32_t i = 0; i < n; ++i)
    {
        for (const auto& [id, w] : records[i]) inst[i].hist.add(id, w);
        labels[i].semantic.add(5, 1.f);
        labels[i].instances = i;
        surfaces[i].labels = i;
        voxels[i].surface = i;
        keys.push_back(VoxelKey{int32_t(i), 0, 0}.packed());
    }
    map.restore(keys, voxels, surfaces, labels, inst, next_id);
}
}  // namespace

TEST(PanopticMapFrame, HitsAndFreeSpaceOfAWall)
{
    PanopticMap map;
    const PanopticFrame f = wallFrame(2.0f);
    const FrameStats st = map.integrate(f, Pose::Identity());
    EXPECT_EQ(st.valid_pixels, 64u * 48u);
    // The wall voxel on the optical axis: one hit, mean exactly on the wall.
    const uint32_t wall = map.voxels().find(map.grid().keyOf({0.01, 0.01, 2.0}));
    ASSERT_NE(wall, kNoRecord);
    EXPECT_FLOAT_EQ(map.voxels()[wall].occ, 0.85f);
    EXPECT_FLOAT_EQ(map.shapeOf(map.voxels()[wall]).mean[2], 2.0f);
    // A voxel halfway: one miss (no Gaussian there).
    const uint32_t mid = map.voxels().find(map.grid().keyOf({0.01, 0.01, 1.05}));
    ASSERT_NE(mid, kNoRecord);
    EXPECT_FLOAT_EQ(map.voxels()[mid].occ, -0.4f);
    // Five more frames: hits clamp at 3.5, misses at -2.
    for (int i = 0; i < 5; ++i) map.integrate(f, Pose::Identity());
    EXPECT_FLOAT_EQ(map.voxels()[wall].occ, 3.5f);
    EXPECT_FLOAT_EQ(map.voxels()[mid].occ, -2.0f);
    // Nothing exists behind the wall.
    EXPECT_EQ(map.voxels().find(map.grid().keyOf({0.01, 0.01, 2.55})), kNoRecord);
}

TEST(PanopticMapFrame, InvalidDepthIsSkippedAndCounted)
{
    PanopticMap map;
    PanopticFrame f = wallFrame(2.0f);
    f.depth.at(0, 0) = std::numeric_limits<float>::quiet_NaN();
    f.depth.at(0, 1) = 0.f;
    f.depth.at(0, 2) = -1.f;
    f.depth.at(0, 3) = std::numeric_limits<float>::infinity();
    f.depth.at(0, 4) = 10.5f;  // beyond max_range = 10
    f.depth.at(0, 5) = 11.f;
    const FrameStats st = map.integrate(f, Pose::Identity());
    EXPECT_EQ(st.skipped_invalid_depth, 4u);
    EXPECT_EQ(st.skipped_over_range, 2u);
    EXPECT_EQ(st.valid_pixels, 64u * 48u - 6u);
}

TEST(PanopticMapFrame, SizeMismatchNamesTheSource)
{
    PanopticMap map;
    PanopticFrame f = wallFrame(2.0f);
    f.semantic.resize(32, 24, 1);
    f.semantic_score.resize(32, 24, 1.f);
    try
    {
        map.integrate(f, Pose::Identity());
        FAIL() << "expected InputError";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("TEST @ 1.0"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("32x24"), std::string::npos) << e.what();
    }
}

TEST(PanopticMapFrame, UnknownClassNamesTheClassAndSource)
{
    PanopticMap map;
    PanopticFrame f = wallFrame(2.0f);
    f.semantic.resize(64, 48, 1);
    f.semantic_score.resize(64, 48, 0.9f);
    f.semantic.at(3, 7) = 57;
    try
    {
        map.integrate(f, Pose::Identity());
        FAIL() << "expected InputError";
    }
    catch (const InputError& e)
    {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("class id 57"), std::string::npos) << msg;
        EXPECT_NE(msg.find("TEST @ 1.0"), std::string::npos) << msg;
        EXPECT_NE(msg.find("row 3, col 7"), std::string::npos) << msg;
    }
    EXPECT_TRUE(map.voxels().empty());  // nothing half-applied
}

TEST(PanopticMapFrame, NonFinitePoseIsRejected)
{
    PanopticMap map;
    Pose T = Pose::Identity();
    T.translation().x() = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(map.integrate(wallFrame(2.f), T), InputError);
}

TEST(PanopticMapFrame, SemanticHistogramCountsPixelsAboveThetaL)
{
    MapOptions o;
    o.theta_l = 0.7;
    PanopticMap map(o);
    PanopticFrame f = wallFrame(2.0f);
    f.semantic.resize(64, 48, 1);          // wall
    f.semantic_score.resize(64, 48, 0.8f);
    const uint32_t below = 0;
    (void)below;
    f.semantic_score.at(24, 32) = 0.7f;    // not > theta_l: ignored
    const FrameStats st = map.integrate(f, Pose::Identity());
    EXPECT_EQ(st.semantic_updates, 64u * 48u - 1u);
    const uint32_t wall = map.voxels().find(map.grid().keyOf({0.01, 0.01, 2.0}));
    const LabelRecord* r = map.labelsOf(map.voxels()[wall]);
    ASSERT_NE(r, nullptr);
    // Pixels of that voxel: cols 32..33 and rows 24..25 (x,y in [0,0.1) at 2 m, f=32).
    EXPECT_EQ(r->n_l, 3u);
    if constexpr (kQuantisedHistograms)
    {
        // PNDT_QUANTISED_HISTOGRAMS: 2.4 to a step of 2^-14.
        EXPECT_NEAR(r->semantic.weightOf(1), 2.4f, 0x1p-14f);
        EXPECT_NEAR(stuffMass(*r, map.options().classes), 2.4f, 0x1p-14f);
    }
    else
    {
        EXPECT_FLOAT_EQ(r->semantic.weightOf(1), 2.4f);
        EXPECT_FLOAT_EQ(stuffMass(*r, map.options().classes), 2.4f);
    }
    EXPECT_EQ(map.semanticLabel(wall), 1);
    EXPECT_EQ(map.labelAt({0.05, 0.05, 2.0}).semantic, 1);
}

TEST(PanopticMapFrame, RenderReproducesTheWall)
{
    PanopticMap map;
    const PanopticFrame f = wallFrame(2.0f);
    for (int i = 0; i < 3; ++i) map.integrate(f, Pose::Identity());
    RenderedView view;
    map.render(Pose::Identity(), f.K, view);
    int hits = 0;
    for (float d : view.depth.data)
        if (d > 0)
        {
            ++hits;
            EXPECT_NEAR(d, 2.0, 0.02);
        }
    EXPECT_GT(hits, 64 * 48 * 9 / 10);
}

TEST(PanopticMapFrame, RenameInstancesMergesAndMovesTheCounter)
{
    std::vector<InstanceRecord> inst(1);
    inst[0].hist.add(1, 3.f);
    inst[0].hist.add(2, 2.f);
    std::vector<LabelRecord> labels(1);
    labels[0].semantic.add(5, 1.f);
    labels[0].instances = 0;
    std::vector<Voxel> voxels(1);
    voxels[0].surface = 0;
    std::vector<SurfaceRecord> surfaces(1);
    surfaces[0].labels = 0;
    PanopticMap map;
    map.restore({VoxelKey{0, 0, 0}.packed()}, voxels, surfaces, labels, inst, 3);
    map.renameInstances([](uint32_t id) { return id == 1 ? 40u : 40u; });  // both -> 40
    const auto& h = map.instanceRecords()[0].hist;
    ASSERT_EQ(h.size(), 1);
    EXPECT_EQ(h.ids[0], 40u);
    EXPECT_FLOAT_EQ(h.weight(0), 5.f);
    EXPECT_EQ(map.nextInstanceId(), 41u);
    map.reserveInstanceIds(100);
    EXPECT_EQ(map.nextInstanceId(), 100u);
}

TEST(PanopticMapFrame, RenameInstancesInARangeAsksOnlyForIdsInIt)
{
    // Three records: ids {1, 7}, {9}, {12, 20}. Range [7, 12]: 7 -> 1 (merged
    // with the 1 beside it), 9 and 12 kept by rename, 1 and 20 never asked
    // about, although rename would move them.
    PanopticMap map;
    restoreInstanceRecords(map, {{{1, 3.f}, {7, 2.f}}, {{9, 1.f}}, {{12, 4.f}, {20, 0.5f}}}, 21);
    std::vector<uint32_t> asked;
    map.renameInstances(
        [&](uint32_t id) {
            asked.push_back(id);
            return id == 7 ? 1u : id == 1 || id == 20 ? 99u : id;
        },
        7, 12);
    std::sort(asked.begin(), asked.end());
    asked.erase(std::unique(asked.begin(), asked.end()), asked.end());
    EXPECT_EQ(asked, (std::vector<uint32_t>{7, 9, 12}));
    const auto& r = map.instanceRecords();
    ASSERT_EQ(r[0].hist.size(), 1);
    EXPECT_EQ(r[0].hist.ids[0], 1u);
    EXPECT_FLOAT_EQ(r[0].hist.weight(0), 5.f);
    ASSERT_EQ(r[1].hist.size(), 1);
    EXPECT_EQ(r[1].hist.ids[0], 9u);
    ASSERT_EQ(r[2].hist.size(), 2);
    EXPECT_EQ(r[2].hist.ids[0], 12u);
    EXPECT_EQ(r[2].hist.ids[1], 20u);
    EXPECT_EQ(map.nextInstanceId(), 21u);
}

TEST(PanopticMapFrame, RenameInstancesMovesTheFramesSeenOfTheRenamedIdsOnly)
{
    // Records hold ids 1, 7, 9 and 12; frames seen also of 2, 3, 4, 20 (no record). 7 ->
    // 1 (the larger count stays), 12 -> 30 (an id without frames seen yet),
    // whether the range is narrower than the table (ids looked up) or not (the
    // table walked).
    const auto rename = [](uint32_t id) { return id == 7 ? 1u : id == 12 ? 30u : id; };
    const std::vector<std::pair<uint32_t, uint32_t>> expected{{1, 5}, {2, 1}, {3, 1}, {4, 1}, {9, 2}, {20, 6}, {30, 4}};
    for (const auto& [first, last] : {std::pair<uint32_t, uint32_t>{7, 12}, {1, UINT32_MAX}})
    {
        SCOPED_TRACE(::testing::Message() << "range " << first << ".." << last);
        PanopticMap map;
        restoreInstanceRecords(map, {{{1, 3.f}, {7, 2.f}}, {{9, 1.f}, {12, 4.f}}}, 21);
        map.restoreInstanceFrames({{1, 3}, {2, 1}, {3, 1}, {4, 1}, {7, 5}, {9, 2}, {12, 4}, {20, 6}});
        map.renameInstances(rename, first, last);
        EXPECT_EQ(map.instanceFrames(), expected);
        EXPECT_EQ(map.nextInstanceId(), 31u);
    }
}

TEST(PanopticMapFrame, RaysFreeTheVoxelsOfTheReferenceWalkInEveryOctantAndAcrossBricks)
{
    // A camera at negative coordinates, near brick corners, looking into each
    // octant in turn, and a few pixels at scattered depths: rays go every way,
    // across many bricks (8 voxels an edge) through faces of every side. The
    // voxels the map frees must be those walkSegment visits (with every ray's
    // count, PerRay), no more, no fewer. One sample per voxel: no Gaussians,
    // every miss the constant one.
    PanopticFrame f;
    f.K = {64, 48, 30.0, 34.0, 31.5, 23.5};
    f.depth.resize(64, 48, 0.f);
    const int pixels[][2] = {{0, 0}, {63, 0}, {0, 47}, {63, 47}, {31, 23}, {10, 40}, {55, 9}, {20, 5}, {44, 30}, {5, 24}};
    const float depths[] = {3.1f, 2.3f, 4.05f, 1.7f, 3.6f, 0.9f, 2.8f, 4.4f, 1.3f, 3.35f};
    for (size_t j = 0; j < std::size(depths); ++j) f.depth.at(pixels[j][1], pixels[j][0]) = depths[j];  // (row, column)
    f.source = "TEST rays";

    for (int octant = 0; octant < 8; ++octant)
        for (MissAccumulation acc : {MissAccumulation::Strongest, MissAccumulation::PerRay})
        {
            SCOPED_TRACE(::testing::Message() << "octant " << octant << (acc == MissAccumulation::PerRay ? ", per ray" : ", strongest"));
            const Eigen::Vector3d view((octant & 1) ? 0.61 : -0.58, (octant & 2) ? 0.52 : -0.66, (octant & 4) ? 0.71 : -0.49);
            Pose T = Pose::Identity();
            T.linear() = (Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), view) *
                          Eigen::AngleAxisd(0.3 + 0.7 * octant, Eigen::Vector3d::UnitZ()))
                             .toRotationMatrix();
            T.translation() = Eigen::Vector3d(-0.797, -0.0031, -1.6013);
            MapOptions o;
            o.ray_mode = RayMode::PerPixel;
            o.miss_accumulation = acc;
            o.log_odds_min = -1e6f;  // no clamping: PerRay's counts show
            PanopticMap map(o);
            const FrameStats st = map.integrate(f, T);
            ASSERT_EQ(st.valid_pixels, std::size(depths));

            // The reference: each pixel's point, the voxels before its voxel, counted per ray.
            std::map<uint64_t, int> crossed;
            std::set<uint64_t> hit;
            for (size_t j = 0; j < std::size(depths); ++j)
            {
                const double z = depths[j];
                const Eigen::Vector3d p = T * Eigen::Vector3d((pixels[j][0] - f.K.cx) / f.K.fx * z,
                                                              (pixels[j][1] - f.K.cy) / f.K.fy * z, z);
                hit.insert(map.grid().keyOf(p).packed());
                walkSegment(map.grid(), T.translation(), p, [&](const VoxelKey& k) {
                    ++crossed[k.packed()];
                    return true;
                });
            }
            ASSERT_EQ(hit.size(), std::size(depths));  // the pixels' voxels are distinct
            size_t freed = 0;
            for (uint32_t i = 0; i < map.voxels().size(); ++i)
            {
                const uint64_t k = map.voxels().key(i).packed();
                const float occ = map.voxels()[i].occ;
                if (hit.count(k))
                {
                    EXPECT_FLOAT_EQ(occ, 0.85f);  // a hit this frame wins over any miss
                    continue;
                }
                const auto it = crossed.find(k);
                ASSERT_NE(it, crossed.end()) << "a voxel no reference ray crossed";
                const int rays = acc == MissAccumulation::PerRay ? it->second : 1;
                EXPECT_FLOAT_EQ(occ, -0.4f * float(rays)) << it->second << " rays";
                ++freed;
            }
            size_t expected = 0, shared = 0;
            for (const auto& [k, n] : crossed)
            {
                expected += hit.count(k) == 0;
                shared += n > 1;
            }
            EXPECT_EQ(freed, expected);
            EXPECT_GT(expected, 150u) << "long rays: many bricks";
            EXPECT_GT(shared, 3u) << "rays sharing voxels near the camera";
        }
}
