#include <pndt/eval/map_eval.h>
#include <pndt/eval/panoptic_codec.h>
#include <pndt/types.h>

#include <string>

namespace pndt::eval
{
PredictedLabels labelPoints(const PanopticMap& map, const std::vector<Eigen::Vector3d>& points, PointLookup lookup)
{
    map.finalize();
    const InstanceNumbering numbering = InstanceNumbering::of(map);
    PredictedLabels out;
    out.semantic.assign(points.size(), 0);
    out.panoptic.assign(points.size(), 0);
    for (size_t i = 0; i < points.size(); ++i)
    {
        uint32_t voxel = kNoRecord;
        if (lookup == PointLookup::Map)
        {
            const PointLabel l = map.labelAt(points[i]);
            if (l.found) voxel = l.voxel;
        }
        else
        {
            const uint32_t vi =
                map.grid().holds(points[i]) ? map.voxels().find(map.grid().keyOf(points[i])) : kNoRecord;
            if (vi != kNoRecord && map.isOccupied(map.voxels()[vi])) voxel = vi;
        }
        if (voxel == kNoRecord) continue;
        const PanopticLabel pl = map.panopticLabel(voxel);
        out.semantic[i] = map.semanticLabel(voxel);
        out.panoptic[i] = encodePanoptic(pl.semantic, numbering.dense(pl.instance));
    }
    return out;
}

PredictedLabels viewLabels(const RenderedView& view, const InstanceNumbering& numbering)
{
    PredictedLabels out;
    out.semantic = view.semantic.data;
    out.panoptic.resize(view.panoptic_semantic.size());
    for (size_t i = 0; i < out.panoptic.size(); ++i)
        out.panoptic[i] = encodePanoptic(view.panoptic_semantic.data[i], numbering.dense(view.instance.data[i]));
    return out;
}

namespace
{
// The labels carry dense numbers; the caller's confidence speaks map ids.
std::vector<InstancePrediction> instancesOf(const PredictedLabels& p, const Benchmark& b, const InstanceConfidence& c,
                                            const InstanceNumbering& numbering)
{
    if (!c) return instancesFromPanoptic(p.panoptic, b, c);
    return instancesFromPanoptic(p.panoptic, b, [&](uint16_t semantic, uint32_t dense) {
        return c(semantic, numbering.mapId(dense));
    });
}
}  // namespace

PredictedLabels evaluatePoints(const PanopticMap& map, const std::vector<Eigen::Vector3d>& points,
                               const std::vector<uint32_t>& gt_panoptic, PanopticEvaluator& eval, PointLookup lookup,
                               const InstanceConfidence& confidence)
{
    if (gt_panoptic.size() != points.size())
        throw InputError("evaluatePoints: " + std::to_string(points.size()) + " points but " +
                         std::to_string(gt_panoptic.size()) + " GT labels");
    PredictedLabels pred = labelPoints(map, points, lookup);
    eval.add(gt_panoptic, pred, instancesOf(pred, eval.benchmark(), confidence, InstanceNumbering::of(map)));
    return pred;
}

PredictedLabels evaluateView(const PanopticMap& map, const Pose& T_world_cam, const CameraIntrinsics& K,
                             const Image<uint16_t>& gt_semantic, const Image<uint32_t>& gt_instance,
                             PanopticEvaluator& eval, RenderedView* view_out, const InstanceConfidence& confidence)
{
    if (!gt_semantic.sameSize(K.width, K.height) || !gt_instance.sameSize(K.width, K.height))
        throw InputError("evaluateView: GT images " + std::to_string(gt_semantic.width) + "x" +
                         std::to_string(gt_semantic.height) + " (semantic) and " + std::to_string(gt_instance.width) +
                         "x" + std::to_string(gt_instance.height) + " (instance) do not match the camera " +
                         std::to_string(K.width) + "x" + std::to_string(K.height));
    RenderedView local;
    RenderedView& view = view_out ? *view_out : local;
    map.render(T_world_cam, K, view);
    const InstanceNumbering numbering = InstanceNumbering::of(map);
    PredictedLabels pred = viewLabels(view, numbering);
    const std::vector<uint32_t> gt = encodePanoptic(gt_semantic.data, gt_instance.data);
    eval.add(gt, pred, instancesOf(pred, eval.benchmark(), confidence, numbering));
    return pred;
}

}  // namespace pndt::eval
