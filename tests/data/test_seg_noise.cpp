// Segmentation noise model (design §10): coherent, temporally correlated, view
// dependent errors; per-frame id permutation; merge rule; informative scores.
#include <gtest/gtest.h>
#include <pndt/data/seg_noise.h>
#include <pndt/data/segment_analysis.h>
#include <pndt/sim/indoor_scene.h>
#include <pndt/sim/nyu40_extra.h>
#include <pndt/sim/scene_builder.h>
#include <pndt/sim/trajectory.h>
#include <pndt/sim/scene_objects.h>
#include <pndt/sim/walk_trajectory.h>

#include <iostream>
#include <map>
#include <set>

#include "data_test_util.h"

using namespace pndt;
using namespace pndt::data;
using test::renderView;
using test::View;

namespace
{
/// A dense walk (many frames per loop, so consecutive views are close) through a room,
/// rendered at low resolution; shared by the tests of this file.
struct Walk
{
    sim::Scene scene;
    std::vector<sim::SceneObject> objects;
    std::vector<Pose> poses;
    std::vector<View> views;
    CameraIntrinsics K = test::smallK();

    Walk(const std::string& preset, int frames, uint64_t seed = 1)
    {
        scene = sim::makeIndoorScene(sim::indoorScenePreset(preset));
        objects = sim::sceneObjects(scene);
        sim::WalkOptions w;
        w.n_frames = frames;
        w.seed = seed;
        poses = sim::walkTrajectory(scene, w);
        for (const Pose& T : poses) views.push_back(renderView(scene, T, K));
    }
    SegNoiseFrame apply(const SegmentationNoiseModel& m, size_t i) const
    {
        return m.apply(views[i].r.semantic, views[i].r.instance, views[i].r.depth, views[i].geo, i);
    }
};

const Walk& denseWalk()
{
    static const Walk w("living", 360);
    return w;
}

bool anyError(const InstanceOutcome& o) { return o.dropped || o.confused || o.split || o.merged; }

}  // namespace

TEST(SegNoise, StrengthZeroIsGroundTruthWithPermutedIds)
{
    const Walk& w = denseWalk();
    SegNoiseOptions o;
    o.strength = 0;
    const SegmentationNoiseModel m(w.objects, o);
    for (size_t i = 0; i < w.views.size(); i += 40)
    {
        const SegNoiseFrame f = w.apply(m, i);
        EXPECT_EQ(f.semantic.data, w.views[i].r.semantic.data);
        std::map<uint32_t, uint32_t> fwd, back;
        for (size_t p = 0; p < f.instance.size(); ++p)
        {
            const uint32_t g = w.views[i].r.instance.data[p], q = f.instance.data[p];
            ASSERT_EQ(g == 0, q == 0);
            if (!g) continue;
            auto [it, ins] = fwd.emplace(g, q);
            EXPECT_EQ(it->second, q);  // one predicted id per object ...
            auto [jt, jns] = back.emplace(q, g);
            EXPECT_EQ(jt->second, g);  // ... and one object per id
        }
        for (size_t p = 0; p < f.semantic.size(); ++p)
        {
            if (f.semantic.data[p])
            {
                EXPECT_FLOAT_EQ(f.semantic_score.data[p], 0.999f);
            }
        }
        EXPECT_EQ(f.phantoms, 0);
    }
}

TEST(SegNoise, InstanceIdsArePermutedEveryFrame)
{
    const Walk& w = denseWalk();
    const SegmentationNoiseModel m(w.objects, SegNoiseOptions{});
    // Ids are 1..K in each frame, and an object's id changes between frames.
    int same = 0, pairs = 0;
    std::map<uint32_t, uint32_t> prev;
    for (size_t i = 0; i < 60; ++i)
    {
        const SegNoiseFrame f = w.apply(m, i);
        std::set<uint32_t> ids;
        for (uint32_t v : f.instance.data)
            if (v) ids.insert(v);
        if (!ids.empty())
        {
            EXPECT_EQ(*ids.begin(), 1u);
            EXPECT_EQ(*ids.rbegin(), ids.size());
        }
        std::map<uint32_t, uint32_t> cur;
        for (const auto& oc : f.outcomes)
            if (oc.pred_instance) cur[oc.gt_instance] = oc.pred_instance;
        for (const auto& [g, id] : cur)
            if (prev.count(g))
            {
                ++pairs;
                same += prev[g] == id;
            }
        prev = cur;
    }
    ASSERT_GT(pairs, 100);
    EXPECT_LT(double(same) / pairs, 0.4);
}

TEST(SegNoise, ThingPixelsFollowTheMergeRuleAndStuffHasNoInstance)
{
    const Walk& w = denseWalk();
    const SegmentationNoiseModel m(w.objects, SegNoiseOptions{});
    for (size_t i = 0; i < w.views.size(); i += 12)
    {
        const SegNoiseFrame f = w.apply(m, i);
        std::map<uint32_t, uint16_t> cls;
        for (size_t p = 0; p < f.semantic.size(); ++p)
        {
            const uint16_t s = f.semantic.data[p];
            const uint32_t id = f.instance.data[p];
            if (sim::nyu40::isThing(s))
            {
                EXPECT_GT(id, 0u) << "thing pixel without instance";
            }
            else
            {
                EXPECT_EQ(id, 0u) << "stuff / void pixel with instance";
            }
            if (!id) continue;
            auto [it, ins] = cls.emplace(id, s);
            EXPECT_EQ(it->second, s) << "instance " << id << " has two classes";
        }
    }
}

TEST(SegNoise, ErrorsAreSpatiallyCoherent)
{
    // Wrong pixels come in segments and bands, not as salt: most wrong pixels have
    // only wrong 4-neighbours (independent noise at the same rate would give ~p^4).
    const Walk& w = denseWalk();
    const SegmentationNoiseModel m(w.objects, SegNoiseOptions{});
    size_t wrong = 0, wrong_inside = 0, valid = 0;
    const int W = w.K.width, H = w.K.height;
    for (size_t i = 0; i < w.views.size(); i += 6)
    {
        const SegNoiseFrame f = w.apply(m, i);
        const auto& gt = w.views[i].r.semantic;
        auto bad = [&](int r, int c) { return gt.at(r, c) && f.semantic.at(r, c) != gt.at(r, c); };
        for (int r = 1; r + 1 < H; ++r)
            for (int c = 1; c + 1 < W; ++c)
            {
                if (!gt.at(r, c)) continue;
                ++valid;
                if (!bad(r, c)) continue;
                ++wrong;
                wrong_inside += bad(r - 1, c) && bad(r + 1, c) && bad(r, c - 1) && bad(r, c + 1);
            }
    }
    const double p = double(wrong) / valid;
    EXPECT_GT(p, 0.05);
    EXPECT_LT(p, 0.5);
    EXPECT_GT(double(wrong_inside) / wrong, 0.6);
}

TEST(SegNoise, ErrorsPersistOverNearbyFramesAlongAWalk)
{
    const Walk& w = denseWalk();
    const SegmentationNoiseModel m(w.objects, SegNoiseOptions{});
    std::map<uint32_t, std::map<size_t, bool>> track;  // object -> frame -> any error
    for (size_t i = 0; i < w.views.size(); ++i)
    {
        const SegNoiseFrame f = w.apply(m, i);
        for (const auto& oc : f.outcomes)
            if (oc.area >= 150) track[oc.gt_instance][i] = anyError(oc);
    }
    double n = 0, n_err = 0, n_ok = 0, err_err = 0, ok_ok = 0;
    for (const auto& [id, frames] : track)
        for (const auto& [i, e] : frames)
        {
            const auto nx = frames.find(i + 1);
            if (nx == frames.end()) continue;
            n += 1;
            if (e)
                n_err += 1, err_err += nx->second;
            else
                n_ok += 1, ok_ok += !nx->second;
        }
    const double p_err = n_err / n;
    std::cout << "[ seg ] walk: P(err) " << p_err << ", P(err | err before) " << err_err / n_err
              << ", P(ok | ok before) " << ok_ok / n_ok << "\n";
    ASSERT_GT(n, 1000);
    EXPECT_GT(p_err, 0.15);
    EXPECT_LT(p_err, 0.8);
    EXPECT_GT(err_err / n_err, p_err + 0.2);
    EXPECT_GT(ok_ok / n_ok, (1 - p_err) + 0.2);
}

TEST(SegNoise, AnErrorLastsWhileTheViewIsSimilarAndIsRedrawnWhenItChanges)
{
    // Orbit round a table at constant distance (difficulty stays about constant), one
    // frame per degree: decisions must agree between neighbouring frames and be
    // unrelated between views more than 60 degrees apart.
    const sim::Scene scene = sim::makeTableWithChairsRoom({});
    const auto objects = sim::sceneObjects(scene);
    const auto poses = sim::orbit({0, 0, 0}, 2.4, 1.6, 0.5, 360);
    const CameraIntrinsics K = test::smallK(128, 96);
    std::vector<View> views;
    for (const Pose& T : poses) views.push_back(renderView(scene, T, K));
    double near_agree = 0, near_n = 0, far_agree = 0, far_n = 0, chance_sum = 0;
    int flips = 0;
    for (uint64_t seed : {1, 2, 3})
    {
        SegNoiseOptions o;
        o.seed = seed;
        o.strength = 1.5;
        const SegmentationNoiseModel m(objects, o);
        std::vector<int> conf, split;
        for (size_t i = 0; i < views.size(); ++i)
        {
            const SegNoiseFrame f =
                m.apply(views[i].r.semantic, views[i].r.instance, views[i].r.depth, views[i].geo, i);
            int c = -1, s = -1;
            for (const auto& oc : f.outcomes)
                if (oc.gt_instance == 1) c = oc.confused, s = oc.split;  // the table
            conf.push_back(c);
            split.push_back(s);
        }
        for (const auto* series : {&conf, &split})
        {
            const auto& v = *series;
            double p = 0, cnt = 0;
            for (int x : v)
                if (x >= 0) p += x, cnt += 1;
            p /= cnt;
            for (size_t i = 0; i < v.size(); ++i)
            {
                const size_t j = (i + 1) % v.size();
                if (v[i] < 0 || v[j] < 0) continue;
                near_n += 1;
                near_agree += v[i] == v[j];
                flips += v[i] != v[j];
                for (size_t k = i + 60; k <= i + 300; k += 7)  // 60..300 deg apart
                {
                    const size_t kk = k % v.size();
                    if (v[kk] < 0) continue;
                    far_n += 1;
                    far_agree += v[i] == v[kk];
                    chance_sum += p * p + (1 - p) * (1 - p);
                }
            }
        }
    }
    const double chance = chance_sum / far_n;
    std::cout << "[ seg ] orbit: agreement next frame " << near_agree / near_n << ", 60-300 deg apart "
              << far_agree / far_n << " (chance " << chance << "), flips " << flips << "\n";
    EXPECT_GT(near_agree / near_n, 0.9);
    EXPECT_LT(far_agree / far_n, chance + 0.12);
    EXPECT_GT(flips, 12);  // the errors do change round the orbit
}

TEST(SegNoise, SmallFarAndOccludedObjectsAreWrongMoreOften)
{
    const Walk& w = denseWalk();
    const SegmentationNoiseModel m(w.objects, SegNoiseOptions{});
    const double img = double(w.K.width) * w.K.height;
    double drop_small = 0, n_small = 0, drop_large = 0, n_large = 0;
    double err_hard = 0, n_hard = 0, err_easy = 0, n_easy = 0;
    for (size_t i = 0; i < w.views.size(); i += 2)
    {
        const SegNoiseFrame f = w.apply(m, i);
        for (const auto& oc : f.outcomes)
        {
            const double a = oc.area / img;
            if (a < 0.003)
                n_small += 1, drop_small += oc.dropped;
            else if (a > 0.03)
                n_large += 1, drop_large += oc.dropped;
            // Class-level errors (missed or given a wrong class); over-segmentation, by
            // contrast, hits large objects more (it needs room to split).
            const bool wrong_class = oc.dropped || oc.confused;
            if (oc.difficulty > 1.5)
                n_hard += 1, err_hard += wrong_class;
            else if (oc.difficulty < 0.5)
                n_easy += 1, err_easy += wrong_class;
        }
    }
    std::cout << "[ seg ] dropped: small " << drop_small / n_small << " vs large " << drop_large / n_large
              << "; missed or wrong class: hard " << err_hard / n_hard << " vs easy " << err_easy / n_easy << "\n";
    ASSERT_GT(n_small, 50);
    ASSERT_GT(n_large, 50);
    EXPECT_GT(drop_small / n_small, 3 * drop_large / n_large + 0.05);
    ASSERT_GT(n_hard, 50);
    ASSERT_GT(n_easy, 50);
    EXPECT_GT(err_hard / n_hard, err_easy / n_easy + 0.15);
}

TEST(SegNoise, DifficultyRisesWithSmallnessDistanceOcclusionAndGrazing)
{
    SegmentInfo s;
    s.area = 20000;  // 6.5 % of 640 x 480
    s.depth_sum = 1.0 * s.area;
    s.depth_n = s.area;
    s.cos_sum = 0.9 * s.area;
    s.cos_n = s.area;
    s.boundary = 400;
    EXPECT_DOUBLE_EQ(segmentDifficulty(s, 640, 480), 0.0);
    SegmentInfo small = s, far = s, occ = s, graz = s;
    small.area = 200;
    far.depth_sum = 4.0 * s.area;
    occ.occluded = 300;
    graz.cos_sum = 0.1 * s.area;
    EXPECT_GT(segmentDifficulty(small, 640, 480), 1.5);
    EXPECT_NEAR(segmentDifficulty(far, 640, 480), 0.5, 1e-9);
    EXPECT_NEAR(segmentDifficulty(occ, 640, 480), 0.75, 1e-9);
    EXPECT_NEAR(segmentDifficulty(graz, 640, 480), 0.6, 1e-9);
    // Resolution independent: the same share of a larger image.
    SegmentInfo big_image = small;
    big_image.area = 4 * small.area;
    EXPECT_NEAR(segmentDifficulty(big_image, 1280, 960), segmentDifficulty(small, 640, 480), 1e-12);
}

TEST(SegNoise, ScoresAreHigherWhereThePredictionIsRight)
{
    const Walk& w = denseWalk();
    const SegmentationNoiseModel m(w.objects, SegNoiseOptions{});
    double s_ok = 0, n_ok = 0, s_bad = 0, n_bad = 0;
    // Rank statistic: P(score of a random right pixel > score of a random wrong one).
    std::vector<int> hist_ok(1025, 0), hist_bad(1025, 0);
    for (size_t i = 0; i < w.views.size(); i += 10)
    {
        const SegNoiseFrame f = w.apply(m, i);
        const auto& gt = w.views[i].r.semantic;
        for (size_t p = 0; p < gt.size(); ++p)
        {
            if (!gt.data[p]) continue;
            const float sc = f.semantic_score.data[p];
            EXPECT_GE(sc, 0.f);
            EXPECT_LE(sc, 0.999f);
            EXPECT_LE(f.panoptic_score.data[p], 0.999f);
            const int b = static_cast<int>(sc * 1024);
            if (f.semantic.data[p] == gt.data[p])
                s_ok += sc, n_ok += 1, hist_ok[b]++;
            else
                s_bad += sc, n_bad += 1, hist_bad[b]++;
        }
    }
    EXPECT_GT(s_ok / n_ok, s_bad / n_bad + 0.15);
    double auc = 0, below = 0;
    for (int b = 0; b < 1025; ++b)
    {
        auc += hist_ok[b] * (below + 0.5 * hist_bad[b]);
        below += hist_bad[b];
    }
    auc /= n_ok * n_bad;
    EXPECT_GT(auc, 0.75);
}

TEST(SegNoise, GroupingErrorsLowerThePanopticScoreNotTheSemanticOne)
{
    // A network's class confidence does not drop because its instance step split an
    // object or merged it with a neighbour: right-class pixels of split / merged
    // objects keep S^L like untouched ones; their S^P (instance confidence) drops.
    const Walk& w = denseWalk();
    const SegmentationNoiseModel m(w.objects, SegNoiseOptions{});
    double sl_clean = 0, sp_clean = 0, n_clean = 0, sl_group = 0, sp_group = 0, n_group = 0;
    for (size_t i = 0; i < w.views.size(); i += 5)
    {
        const SegNoiseFrame f = w.apply(m, i);
        std::map<uint32_t, const InstanceOutcome*> by_gt;
        for (const auto& o : f.outcomes) by_gt[o.gt_instance] = &o;
        const auto& gt_i = w.views[i].r.instance;
        const auto& gt_s = w.views[i].r.semantic;
        for (size_t p = 0; p < gt_i.size(); ++p)
        {
            const auto it = by_gt.find(gt_i.data[p]);
            if (it == by_gt.end() || f.semantic.data[p] != gt_s.data[p] || f.instance.data[p] == 0) continue;
            const InstanceOutcome& o = *it->second;
            if (o.dropped || o.confused) continue;
            const bool grouped = o.split || o.merged;
            (grouped ? sl_group : sl_clean) += f.semantic_score.data[p];
            (grouped ? sp_group : sp_clean) += f.panoptic_score.data[p];
            (grouped ? n_group : n_clean) += 1;
        }
    }
    ASSERT_GT(n_group, 1000);
    ASSERT_GT(n_clean, 1000);
    EXPECT_NEAR(sl_group / n_group, sl_clean / n_clean, 0.05);
    EXPECT_LT(sp_group / n_group, sp_clean / n_clean - 0.15);
}

TEST(SegNoise, StrongerNoiseMeansMoreErrors)
{
    const Walk& w = denseWalk();
    double prev = -1;
    for (double s : {0.0, 0.5, 1.0, 2.0})
    {
        SegNoiseOptions o;
        o.strength = s;
        const SegmentationNoiseModel m(w.objects, o);
        size_t wrong = 0, valid = 0;
        for (size_t i = 0; i < w.views.size(); i += 20)
        {
            const SegNoiseFrame f = w.apply(m, i);
            for (size_t p = 0; p < f.semantic.size(); ++p)
            {
                const uint16_t g = w.views[i].r.semantic.data[p];
                valid += g != 0;
                wrong += g != 0 && f.semantic.data[p] != g;
            }
        }
        const double rate = double(wrong) / valid;
        if (s == 0)
        {
            EXPECT_EQ(rate, 0.0);
        }
        EXPECT_GT(rate, prev);
        prev = rate;
    }
}

TEST(SegNoise, DeterministicForSeedAndFrame)
{
    const Walk& w = denseWalk();
    const SegmentationNoiseModel m(w.objects, SegNoiseOptions{});
    const SegNoiseFrame a = w.apply(m, 5), b = w.apply(m, 5);
    EXPECT_EQ(a.semantic.data, b.semantic.data);
    EXPECT_EQ(a.instance.data, b.instance.data);
    EXPECT_EQ(a.semantic_score.data, b.semantic_score.data);
    EXPECT_EQ(a.panoptic_score.data, b.panoptic_score.data);
    SegNoiseOptions o;
    o.seed = 9;
    const SegmentationNoiseModel m2(w.objects, o);
    EXPECT_NE(w.apply(m2, 5).instance.data, a.instance.data);
}
