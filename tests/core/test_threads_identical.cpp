// integrate() with several threads gives the map of one thread, bit for bit:
// every voxel, shape, histogram and counter, for every ray mode and ablation;
// and so does every SIMD version of the per-pixel kernels.
#include <gtest/gtest.h>
#include <pndt/panoptic_map.h>
#include <pndt/sim/renderer.h>
#include <pndt/sim/scene_builder.h>
#include <pndt/sim/trajectory.h>

#include <cstring>
#include <random>

#include "projection_kernels.h"

using namespace pndt;

namespace
{
struct Frames
{
    std::vector<PanopticFrame> frames;
    std::vector<Pose> poses;
};

/// The synthetic room along an orbit; instance ids permuted every frame (so
/// matching has to work), scores noisy per pixel (so histogram runs break), a
/// few invalid depths.
Frames roomFrames(int n, int width, int height)
{
    sim::TableRoomOptions ro;
    ro.add_pole = true;
    const sim::Scene scene = sim::makeTableWithChairsRoom(ro);
    const double s = width / 320.0;
    const CameraIntrinsics K{width, height, 262.5 * s, 262.5 * s, (width - 1) / 2.0, (height - 1) / 2.0};
    Frames out;
    out.poses = sim::orbit({0, 0, 0}, 2.2, 1.4, 0.5, n);
    std::mt19937 rng(4);
    std::uniform_int_distribution<uint32_t> id(100, 100000);
    std::uniform_real_distribution<float> score(0.55f, 1.0f);
    sim::RenderedFrame r;
    for (const Pose& T : out.poses)
    {
        sim::render(scene, T, K, r, 8.0);
        PanopticFrame f;
        f.K = K;
        f.depth = r.depth;
        for (size_t i = 0; i < f.depth.data.size(); i += 97) f.depth.data[i] = 0.f;
        f.semantic = r.semantic;
        f.semantic_score.resize(width, height);
        for (float& x : f.semantic_score.data) x = score(rng);
        f.instance = r.instance;
        uint32_t perm[64];
        for (auto& p : perm) p = id(rng);
        for (auto& z : f.instance.data) z = z ? perm[z % 64] : 0;
        f.panoptic_score.resize(width, height);
        for (float& x : f.panoptic_score.data) x = score(rng) - 0.4f;
        out.frames.push_back(std::move(f));
    }
    return out;
}

struct Built
{
    PanopticMap map;
    FrameStats totals;
};

Built build(const Frames& d, MapOptions o)
{
    Built b{PanopticMap(o), {}};
    for (size_t i = 0; i < d.frames.size(); ++i) b.totals += b.map.integrate(d.frames[i], d.poses[i]);
    return b;
}

void expectIdentical(const Built& a, const Built& b)
{
    const PanopticMap &x = a.map, &y = b.map;
    ASSERT_EQ(x.voxels().size(), y.voxels().size());
    EXPECT_EQ(x.voxels().packedKeys(), y.voxels().packedKeys());
    EXPECT_EQ(0, std::memcmp(x.voxels().voxels().data(), y.voxels().voxels().data(), sizeof(Voxel) * x.voxels().size()));
    EXPECT_EQ(x.pairEvidence(), y.pairEvidence());
    ASSERT_EQ(x.surfaceRecords().size(), y.surfaceRecords().size());
    EXPECT_EQ(0, std::memcmp(x.surfaceRecords().data(), y.surfaceRecords().data(),
                             sizeof(SurfaceRecord) * x.surfaceRecords().size()));
    ASSERT_EQ(x.labelRecords().size(), y.labelRecords().size());
    for (size_t i = 0; i < x.labelRecords().size(); ++i)
    {
        const LabelRecord &p = x.labelRecords()[i], &q = y.labelRecords()[i];
        ASSERT_EQ(p.semantic.size(), q.semantic.size()) << i;
        EXPECT_EQ(0, std::memcmp(p.semantic.ids, q.semantic.ids, sizeof(p.semantic.ids)));
        EXPECT_TRUE(p.semantic.weights == q.semantic.weights) << i;
        EXPECT_EQ(p.n_l, q.n_l);
        EXPECT_EQ(p.instances, q.instances);
    }
    ASSERT_EQ(x.instanceRecords().size(), y.instanceRecords().size());
    for (size_t i = 0; i < x.instanceRecords().size(); ++i)
    {
        EXPECT_EQ(x.instanceRecords()[i].n_z, y.instanceRecords()[i].n_z);
        const auto &p = x.instanceRecords()[i].hist, &q = y.instanceRecords()[i].hist;
        ASSERT_EQ(p.size(), q.size());
        EXPECT_EQ(0, std::memcmp(p.ids, q.ids, sizeof(p.ids)));
        EXPECT_TRUE(p.weights == q.weights) << i;
    }
    EXPECT_EQ(x.nextInstanceId(), y.nextInstanceId());
    EXPECT_EQ(x.instanceFrames(), y.instanceFrames());
    const auto sx = x.semanticSpills().sorted(), sy = y.semanticSpills().sorted();
    ASSERT_EQ(sx.size(), sy.size());
    for (size_t i = 0; i < sx.size(); ++i)
    {
        EXPECT_EQ(sx[i].first, sy[i].first);
        ASSERT_EQ(sx[i].second->entries.size(), sy[i].second->entries.size());
        for (size_t j = 0; j < sx[i].second->entries.size(); ++j)
        {
            EXPECT_EQ(sx[i].second->entries[j].cls, sy[i].second->entries[j].cls);
            EXPECT_EQ(sx[i].second->entries[j].weight, sy[i].second->entries[j].weight);
        }
    }
    const FrameStats &s = a.totals, &t = b.totals;
    EXPECT_EQ(s.valid_pixels, t.valid_pixels);
    EXPECT_EQ(s.skipped_invalid_depth, t.skipped_invalid_depth);
    EXPECT_EQ(s.hit_voxels, t.hit_voxels);
    EXPECT_EQ(s.rays, t.rays);
    EXPECT_EQ(s.ray_steps, t.ray_steps);
    EXPECT_EQ(s.missed_voxels, t.missed_voxels);
    EXPECT_EQ(s.predicted_instances, t.predicted_instances);
    EXPECT_EQ(s.matched_instances, t.matched_instances);
    EXPECT_EQ(s.new_instances, t.new_instances);
    EXPECT_EQ(s.ambiguous_instances, t.ambiguous_instances);
    EXPECT_EQ(s.semantic_updates, t.semantic_updates);
    EXPECT_EQ(s.instance_updates, t.instance_updates);
    const auto ia = x.instances(), ib = y.instances();
    ASSERT_EQ(ia.size(), ib.size());
    for (size_t i = 0; i < ia.size(); ++i)
    {
        EXPECT_EQ(ia[i].id, ib[i].id);
        EXPECT_EQ(ia[i].semantic, ib[i].semantic);
        EXPECT_EQ(ia[i].voxel_count, ib[i].voxel_count);
    }
}
}  // namespace

TEST(ThreadsIdentical, AnyThreadCountGivesTheSameMap)
{
    const Frames d = roomFrames(10, 320, 240);
    MapOptions o;
    o.threads = 1;
    const Built one = build(d, o);
    ASSERT_GT(one.map.instanceRecords().size(), 10u);
    ASSERT_GT(one.totals.matched_instances, 10u);
    // A frame's update counts (counted per run, not per pixel) are what its histograms
    // gained: on the first frame, the sums of n_l and n_z.
    {
        PanopticMap first(o);
        const FrameStats st = first.integrate(d.frames[0], d.poses[0]);
        uint64_t n_l = 0, n_z = 0;
        for (const LabelRecord& r : first.labelRecords()) n_l += r.n_l;
        for (const InstanceRecord& r : first.instanceRecords()) n_z += r.n_z;
        EXPECT_EQ(st.semantic_updates, n_l);
        EXPECT_EQ(st.instance_updates, n_z);
        EXPECT_GT(n_z, 10000u);
    }
    for (int threads : {2, 3, 8})
    {
        SCOPED_TRACE(threads);
        o.threads = threads;
        expectIdentical(one, build(d, o));
    }
}

// The per-pixel kernels (projection, predicted instances, vtou
// rows) in every version this CPU has give the scalar code's map, at 10 and 5 cm,
// with one and three threads.
TEST(ThreadsIdentical, EverySimdVersionGivesTheScalarMap)
{
    const Frames d = roomFrames(8, 640, 480);
    const SimdCap before = simdCap();
    for (double voxel : {0.1, 0.05})
        for (int threads : {1, 3})
        {
            MapOptions o;
            o.voxel_size = voxel;
            o.threads = threads;
            setSimdCap(SimdCap::Scalar);
            const Built scalar = build(d, o);
            ASSERT_GT(scalar.totals.matched_instances, 10u);
            for (SimdCap cap : {SimdCap::Sse2, SimdCap::Avx2, SimdCap::Avx512})
            {
                SCOPED_TRACE(testing::Message() << "voxel " << voxel << ", threads " << threads << ", cap " << int(cap));
                setSimdCap(cap);
                expectIdentical(scalar, build(d, o));
            }
        }
    setSimdCap(before);
}

TEST(ThreadsIdentical, FineVoxelsPerPixelRaysAndCubes)
{
    const Frames d = roomFrames(5, 256, 192);
    for (int variant = 0; variant < 3; ++variant)
    {
        SCOPED_TRACE(variant);
        MapOptions o;
        if (variant == 0) o.voxel_size = 0.04;
        if (variant == 1) o.ray_mode = RayMode::PerPixel;
        if (variant == 2) o.use_ndt = false;
        o.threads = 1;
        const Built one = build(d, o);
        o.threads = 3;
        expectIdentical(one, build(d, o));
    }
}

TEST(ThreadsIdentical, ThePapersPerRayMissesAndDenseHistograms)
{
    // Per-ray misses (summed as integers) and h^L without eviction (spills
    // applied after the parallel pass): again the same bits for any thread count.
    Frames d = roomFrames(6, 256, 192);
    // Half the pixels a random class: voxels see more than 8 classes.
    std::mt19937 rng(9);
    std::uniform_int_distribution<int> cls(1, 40), coin(0, 1);
    for (PanopticFrame& f : d.frames)
        for (auto& c : f.semantic.data)
            if (coin(rng)) c = uint16_t(cls(rng));
    for (int variant = 0; variant < 3; ++variant)
    {
        SCOPED_TRACE(variant);
        MapOptions o;
        if (variant != 2) o.miss_accumulation = MissAccumulation::PerRay;
        if (variant == 1) o.ray_mode = RayMode::PerPixel;
        if (variant == 2) o.semantic_eviction = false;
        o.threads = 1;
        const Built one = build(d, o);
        if (variant == 2)
        {
            ASSERT_GT(one.map.semanticSpills().size(), 100u);
        }
        for (int threads : {2, 3})
        {
            o.threads = threads;
            expectIdentical(one, build(d, o));
        }
    }
}

TEST(ThreadsIdentical, SplitPredictionsAndInstanceClasses)
{
    // From the third frame on, every other frame predicts all things as one
    // instance: that prediction swallows map instances of other classes, so the
    // split rule (classes of the map instances in view, split pixels written in
    // row bands) runs with many voxels, and must give the same bits.
    Frames d = roomFrames(8, 640, 480);
    for (size_t i = 2; i < d.frames.size(); i += 2)
        for (auto& z : d.frames[i].instance.data) z = z ? 7 : 0;
    MapOptions o;
    o.voxel_size = 0.05;
    o.threads = 1;
    const Built one = build(d, o);
    ASSERT_GT(one.totals.split_predictions, 2u);
    for (int threads : {2, 3})
    {
        SCOPED_TRACE(threads);
        o.threads = threads;
        const Built many = build(d, o);
        EXPECT_EQ(one.totals.split_predictions, many.totals.split_predictions);
        expectIdentical(one, many);
    }
}

TEST(ThreadsIdentical, ThreadsCanChangeBetweenFrames)
{
    // A copy of a map continues like the original, whatever its thread count.
    const Frames d = roomFrames(6, 256, 192);
    MapOptions o;
    Built a{PanopticMap(o), {}}, b{PanopticMap(o), {}};
    for (size_t i = 0; i < 3; ++i) a.totals += a.map.integrate(d.frames[i], d.poses[i]);
    o.threads = 2;
    b.map = PanopticMap(o);
    const auto vec = [](const auto& pool) { return std::vector(pool.begin(), pool.end()); };
    b.map.restore(a.map.voxels().packedKeys(), vec(a.map.voxels().voxels()), vec(a.map.surfaceRecords()),
                  vec(a.map.labelRecords()), vec(a.map.instanceRecords()), a.map.nextInstanceId());
    b.map.restorePairEvidence(a.map.pairEvidence());
    b.map.restoreInstanceFrames(a.map.instanceFrames());
    b.totals = a.totals;
    for (size_t i = 3; i < d.frames.size(); ++i)
    {
        a.totals += a.map.integrate(d.frames[i], d.poses[i]);
        b.totals += b.map.integrate(d.frames[i], d.poses[i]);
    }
    expectIdentical(a, b);
}
