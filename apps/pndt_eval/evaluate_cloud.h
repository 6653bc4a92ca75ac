// 3D: a map against GT points (design §9): every point labelled with labelAt.
#pragma once

#include <pndt/eval/gt_points.h>
#include <pndt/eval/panoptic_evaluator.h>
#include <pndt/panoptic_map.h>

#include <string>

namespace pndt::evalapp
{
struct CloudScores
{
    eval::EvalResult result;
    size_t points = 0;
    size_t labelled = 0;  ///< points the map gave a label (a voxel near enough)
    double labelledShare() const { return points ? double(labelled) / double(points) : 0.0; }
};

/// Scores `map` on `gt` (AP with the map's instance confidences). With `export_dir` set,
/// writes the predictions as the ScanNet benchmark scripts read them: semantic/<name>.txt,
/// panoptic/<name>.txt (sem << 16 | n, n = the map's dense instance number) and
/// semantic_instance/<name>.txt + predicted_masks/ (one mask file per instance).
CloudScores evaluateCloud(const PanopticMap& map, const eval::GtPoints& gt, const eval::Benchmark& bench,
                          const std::string& export_dir = {}, const std::string& name = {});
}  // namespace pndt::evalapp
