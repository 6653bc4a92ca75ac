// Evaluation of a PanopticMap (design §9, paper §IV-B): 3D by labelling the points of a GT
// cloud with the map, 2D by rendering the map into the camera of an evaluated frame.
#pragma once

#include <pndt/eval/panoptic_evaluator.h>
#include <pndt/instance_numbering.h>
#include <pndt/panoptic_map.h>

#include <Eigen/Core>
#include <functional>
#include <vector>

namespace pndt::eval
{
enum class PointLookup
{
    /// PanopticMap::labelAt: for an NDT map the Gaussian nearest in Mahalanobis distance
    /// among the own voxel and its 26 neighbours (the containing voxel when none has a
    /// usable Gaussian); for a use_ndt = false map the containing voxel ("w/o NDT").
    Map,
    /// The containing voxel only, whatever the map's use_ndt (a query-side ablation; the
    /// paper's "w/o NDT" is a map built with use_ndt = false, evaluated with Map).
    ContainingVoxel,
};

/// Instance score for AP: (semantic, map instance id) -> confidence. Empty = 1.0. It is
/// called with the map's own instance id, not the dense number the labels carry.
using InstanceConfidence = std::function<double(uint16_t semantic, uint32_t instance)>;

/// The map's labels for GT points; a point without an occupied voxel is void (0). Instances
/// are encoded sem << 16 | n with n the map's dense instance number (InstanceNumbering::of,
/// so maps after a short-term hand-over, whose ids exceed 65535, evaluate too).
PredictedLabels labelPoints(const PanopticMap& map, const std::vector<Eigen::Vector3d>& points,
                            PointLookup lookup = PointLookup::Map);

/// The map's labels of a rendered view, row-major (see PanopticMap::render), instances
/// numbered by `numbering` (InstanceNumbering::of the rendered map).
PredictedLabels viewLabels(const RenderedView& view, const InstanceNumbering& numbering);

/// 3D evaluation of one scene: labels `points`, adds them against `gt_panoptic`
/// (sem << 16 | ins per point) to `eval`; returns the labels (for the text writers).
PredictedLabels evaluatePoints(const PanopticMap& map, const std::vector<Eigen::Vector3d>& points,
                               const std::vector<uint32_t>& gt_panoptic, PanopticEvaluator& eval,
                               PointLookup lookup = PointLookup::Map, const InstanceConfidence& confidence = {});

/// 2D evaluation of one frame: renders the map into (T_world_cam, K), adds the view against
/// the frame's GT images (K's size; semantic class, instance id <= 65535) to `eval`.
/// `view` (optional) receives the rendering (for the PNG writers). Throws InputError on a
/// size mismatch.
PredictedLabels evaluateView(const PanopticMap& map, const Pose& T_world_cam, const CameraIntrinsics& K,
                             const Image<uint16_t>& gt_semantic, const Image<uint32_t>& gt_instance,
                             PanopticEvaluator& eval, RenderedView* view = nullptr,
                             const InstanceConfidence& confidence = {});

}  // namespace pndt::eval
