// 3D and 2D evaluation of a tiny hand-made PanopticMap: a wall at z = 2.05 m, its left half
// labelled wall (stuff), its right half a picture (thing, one instance).
#include <gtest/gtest.h>
#include <pndt/eval/class_table.h>
#include <pndt/eval/map_eval.h>
#include <pndt/eval/panoptic_codec.h>

#include <cmath>

#include "labelled_wall.h"

using namespace pndt;
using namespace pndt::eval;

namespace
{
using namespace wall_scene;

PanopticMap buildMap(bool use_ndt)
{
    MapOptions o;
    o.use_ndt = use_ndt;
    PanopticMap map(o);
    const PanopticFrame f = labelledWall();
    for (int i = 0; i < 4; ++i) map.integrate(f, Pose::Identity());
    return map;
}

/// Voxel-centre points on the wall: x in +-{0.05 .. 0.85}, y in {-0.85 .. 0.85}: 9 x 18 = 162 per side.
std::vector<Eigen::Vector3d> wallPoints(bool right)
{
    std::vector<Eigen::Vector3d> p;
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 18; ++j) p.emplace_back((right ? 1 : -1) * (0.05 + 0.1 * i), -0.85 + 0.1 * j, kDepth);
    return p;
}
}  // namespace

TEST(MapEval3D, LabelAtGivesTheClassOnTheWallAndVoidFarAway)
{
    for (bool ndt : {true, false})
    {
        SCOPED_TRACE(ndt ? "NDT" : "w/o NDT");
        const PanopticMap map = buildMap(ndt);
        const PredictedLabels left = labelPoints(map, wallPoints(false));
        for (size_t i = 0; i < left.size(); ++i)
        {
            EXPECT_EQ(left.semantic[i], kWall) << i;
            EXPECT_EQ(left.panoptic[i], encodePanoptic(kWall, 0)) << i;
        }
        const PredictedLabels right = labelPoints(map, wallPoints(true));
        const uint32_t z = instanceOf(right.panoptic[0]);
        EXPECT_NE(z, 0u);
        for (size_t i = 0; i < right.size(); ++i)
        {
            EXPECT_EQ(right.semantic[i], kPicture) << i;
            EXPECT_EQ(right.panoptic[i], encodePanoptic(kPicture, z)) << i;
        }
        // Far from any surface: void.
        const PredictedLabels far = labelPoints(map, {{0.05, 0.05, 6.0}, {5.0, 5.0, kDepth}, {0.05, 0.05, 1.0}});
        EXPECT_EQ(far.semantic, (std::vector<uint16_t>{0, 0, 0}));
        EXPECT_EQ(far.panoptic, (std::vector<uint32_t>{0, 0, 0}));
    }
}

TEST(MapEval3D, NdtLookupReachesTheNeighbourVoxelTheCubeLookupDoesNot)
{
    const PanopticMap map = buildMap(true);
    // 8 cm behind the wall: in the (empty) voxel behind it.
    const Eigen::Vector3d behind(-0.45, 0.05, kDepth + 0.08);
    EXPECT_EQ(labelPoints(map, {behind}, PointLookup::Map).semantic[0], kWall);
    EXPECT_EQ(labelPoints(map, {behind}, PointLookup::ContainingVoxel).semantic[0], 0);
    // On the wall both agree.
    const Eigen::Vector3d on(-0.45, 0.05, kDepth);
    EXPECT_EQ(labelPoints(map, {on}, PointLookup::ContainingVoxel).semantic[0], kWall);
}

TEST(MapEval3D, MetricsOfHandLabelledPoints)
{
    const PanopticMap map = buildMap(true);
    std::vector<Eigen::Vector3d> pts = wallPoints(false);
    std::vector<uint32_t> gt(pts.size(), encodePanoptic(kWall, 0));
    for (const auto& p : wallPoints(true))
    {
        pts.push_back(p);
        gt.push_back(encodePanoptic(kPicture, 7));  // GT instance ids need not equal the map's
    }
    // Two GT floor points far from the map: predicted void.
    pts.emplace_back(0.05, 1.45, 0.5);
    pts.emplace_back(0.15, 1.45, 0.5);
    gt.push_back(encodePanoptic(kFloor, 0));
    gt.push_back(encodePanoptic(kFloor, 0));

    PanopticEvaluator ev(Benchmark::scannet20());
    const PredictedLabels pred = evaluatePoints(map, pts, gt, ev);
    EXPECT_EQ(pred.semantic.back(), 0);
    const EvalResult r = ev.result();
    // IoU: wall 1, picture 1, floor 0 (2 FN) -> mIoU 2/3; the same for mIoU_P.
    EXPECT_DOUBLE_EQ(r.semantic.find(kWall)->iou, 1.0);
    EXPECT_DOUBLE_EQ(r.semantic.find(kPicture)->iou, 1.0);
    EXPECT_DOUBLE_EQ(r.semantic.find(kFloor)->iou, 0.0);
    EXPECT_DOUBLE_EQ(r.semantic.miou, 2.0 / 3);
    EXPECT_DOUBLE_EQ(r.panoptic_semantic.miou, 2.0 / 3);
    // PQ: wall TP (IoU 1), picture TP (IoU 1), floor FN -> PQ 2/3; things 1; stuff 1/2.
    EXPECT_DOUBLE_EQ(r.pq.all.pq, 2.0 / 3);
    EXPECT_DOUBLE_EQ(r.pq.all.sq, 2.0 / 3);  // floor: SQ 0 (no TP), as in TF/nicr
    EXPECT_DOUBLE_EQ(r.pq.things.pq, 1.0);
    EXPECT_DOUBLE_EQ(r.pq.stuff.pq, 0.5);
    // AP50: one picture instance of 162 points, predicted exactly -> 1.
    EXPECT_DOUBLE_EQ(r.ap.ap50, 1.0);

    const ClassTable t = perClassTable(r, ev.benchmark(), "tiny");
    EXPECT_DOUBLE_EQ(t.value(kPicture, "PQ"), 1.0);
    EXPECT_DOUBLE_EQ(t.value(kFloor, "IoU"), 0.0);
    EXPECT_TRUE(std::isnan(t.value(kWall, "AP50")));
    EXPECT_TRUE(std::isnan(t.value(3, "IoU")));  // cabinet: no GT
    EXPECT_DOUBLE_EQ(t.summary[0].values[0], 2.0 / 3);

    EXPECT_THROW(evaluatePoints(map, pts, std::vector<uint32_t>(3), ev), InputError);
}

TEST(MapEval2D, RenderedViewAgainstTheFrameGt)
{
    const PanopticMap map = buildMap(true);
    const PanopticFrame f = labelledWall();
    PanopticEvaluator ev(Benchmark::scannet20());
    RenderedView view;
    const PredictedLabels pred = evaluateView(map, Pose::Identity(), f.K, f.semantic, f.instance, ev, &view);
    ASSERT_EQ(pred.size(), size_t(64 * 48));
    EXPECT_EQ(pred.semantic, view.semantic.data);
    size_t rendered = 0, correct = 0;
    for (size_t i = 0; i < pred.size(); ++i)
    {
        rendered += pred.semantic[i] != 0;
        correct += pred.semantic[i] == f.semantic.data[i];
        EXPECT_EQ(semanticOf(pred.panoptic[i]), view.panoptic_semantic.data[i]);
        EXPECT_EQ(instanceOf(pred.panoptic[i]), view.instance.data[i]);
    }
    EXPECT_GT(rendered, pred.size() * 9 / 10);
    const EvalResult r = ev.result();
    // Every rendered pixel carries its true class, so each class's IoU is its rendered share.
    EXPECT_EQ(correct, rendered);
    EXPECT_GT(r.semantic.miou, 0.9);
    // One segment per class, each matched (IoU > 0.5): RQ 1.
    EXPECT_EQ(r.pq.find(kWall)->tp, 1u);
    EXPECT_EQ(r.pq.find(kPicture)->tp, 1u);
    EXPECT_DOUBLE_EQ(r.pq.all.rq, 1.0);
    EXPECT_GT(r.pq.all.pq, 0.9);
    EXPECT_DOUBLE_EQ(r.ap.ap50, 1.0);

    pndt::Image<uint16_t> small(8, 8);
    pndt::Image<uint32_t> small_i(8, 8);
    EXPECT_THROW(evaluateView(map, Pose::Identity(), f.K, small, small_i, ev), InputError);
}

TEST(MapEval3D, MapsWithInstanceIdsAbove16BitsEvaluateLikeTheFirstMap)
{
    // A short-term map after a hand-over numbers its instances from a block above 65535; its
    // evaluation numbers them densely and gives the same labels and metrics as the first map.
    const PanopticMap first = buildMap(true);
    MapOptions o;
    PanopticMap later(o);
    later.reserveInstanceIds(2 * 65536 + 1);
    const PanopticFrame f = labelledWall();
    for (int i = 0; i < 4; ++i) later.integrate(f, Pose::Identity());
    ASSERT_EQ(later.instances().size(), 1u);
    EXPECT_EQ(later.instances()[0].id, 2u * 65536 + 1);

    std::vector<Eigen::Vector3d> pts = wallPoints(false);
    for (const auto& p : wallPoints(true)) pts.push_back(p);
    std::vector<uint32_t> gt(pts.size(), encodePanoptic(kWall, 0));
    for (size_t i = pts.size() / 2; i < pts.size(); ++i) gt[i] = encodePanoptic(kPicture, 7);

    PanopticEvaluator ev_first(Benchmark::scannet20()), ev_later(Benchmark::scannet20());
    std::vector<uint32_t> confidence_asked;
    const InstanceConfidence confidence = [&](uint16_t, uint32_t id) {
        confidence_asked.push_back(id);
        return 0.5;
    };
    const PredictedLabels a = evaluatePoints(first, pts, gt, ev_first);
    const PredictedLabels b = evaluatePoints(later, pts, gt, ev_later, PointLookup::Map, confidence);
    EXPECT_EQ(b.panoptic, a.panoptic);
    EXPECT_EQ(instanceOf(b.panoptic.back()), 1u);
    EXPECT_DOUBLE_EQ(ev_later.result().pq.all.pq, ev_first.result().pq.all.pq);
    EXPECT_DOUBLE_EQ(ev_later.result().ap.ap50, 1.0);
    // The confidence callback speaks the map's own ids.
    ASSERT_FALSE(confidence_asked.empty());
    for (uint32_t id : confidence_asked) EXPECT_EQ(id, 2u * 65536 + 1);

    // 2D: the rendered view too.
    PanopticEvaluator ev2(Benchmark::scannet20());
    RenderedView view;
    const PredictedLabels v = evaluateView(later, Pose::Identity(), f.K, f.semantic, f.instance, ev2, &view);
    const InstanceNumbering numbering = InstanceNumbering::of(later);
    for (size_t i = 0; i < v.size(); ++i)
    {
        EXPECT_EQ(instanceOf(v.panoptic[i]), numbering.dense(view.instance.data[i]));
        EXPECT_LE(instanceOf(v.panoptic[i]), 1u);
    }
    EXPECT_DOUBLE_EQ(ev2.result().ap.ap50, 1.0);
}
