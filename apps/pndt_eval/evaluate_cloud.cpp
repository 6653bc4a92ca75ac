#include "evaluate_cloud.h"

#include <pndt/eval/label_text.h>
#include <pndt/eval/map_eval.h>
#include <pndt/eval/scannet_instances.h>
#include <pndt/instance_numbering.h>

#include <filesystem>
#include <unordered_map>

namespace pndt::evalapp
{
namespace fs = std::filesystem;

CloudScores evaluateCloud(const PanopticMap& map, const eval::GtPoints& gt, const eval::Benchmark& bench,
                          const std::string& export_dir, const std::string& name)
{
    const eval::PredictedLabels pred = eval::labelPoints(map, gt.points);
    const InstanceNumbering numbering = InstanceNumbering::of(map);
    std::unordered_map<uint32_t, double> confidence_of;
    for (const MapInstance& mi : map.instances()) confidence_of[mi.id] = mi.confidence;
    const auto confidence = [&](uint16_t, uint32_t dense) { return confidence_of.at(numbering.mapId(dense)); };
    const std::vector<eval::InstancePrediction> instances = eval::instancesFromPanoptic(pred.panoptic, bench, confidence);

    eval::PanopticEvaluator ev(bench);
    ev.add(gt.labels, pred, instances);
    CloudScores s;
    s.result = ev.result();
    s.points = gt.points.size();
    for (uint32_t p : pred.panoptic) s.labelled += p != 0;

    if (!export_dir.empty())
    {
        const fs::path dir(export_dir);
        fs::create_directories(dir / "semantic");
        fs::create_directories(dir / "panoptic");
        fs::create_directories(dir / "semantic_instance");
        eval::writeSemanticText((dir / "semantic" / (name + ".txt")).string(), pred.semantic);
        eval::writePanopticText((dir / "panoptic" / (name + ".txt")).string(), pred.panoptic);
        eval::writeScanNetInstances3D((dir / "semantic_instance").string(), name, instances, gt.points.size());
    }
    return s;
}
}  // namespace pndt::evalapp
