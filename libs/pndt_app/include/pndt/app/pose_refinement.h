// Frame-to-map pose refinement in the apps (issue #22): wraps pndt::refine::PoseRefiner,
// refines each frame against the current short-term map and records the poses used, which
// are written as a TUM file beside the maps (refined_poses.tum).
#pragma once

#include <pndt/panoptic_map.h>
#include <pndt/refine/pose_refiner.h>
#include <pndt/refine/time_offset.h>

#include <string>
#include <vector>

namespace pndt::app
{
/// Sets one option from "key=value" (keys as the RefineOptions members: loss=cauchy|huber|none,
/// loss_scale, gate_sigma, min_sigma_ratio, fine_sigma_ratio, min_samples, stuff_weight,
/// thing_weight, void_weight, class_weight=<id>:<w>, max_points, pixel_step, subsample_voxel,
/// max_depth, outer_iterations, max_iterations, min_points, min_eigen_ratio,
/// max_step_translation, max_step_rotation, max_total_translation, max_total_rotation,
/// carry_correction, fallback_keeps_correction). Throws std::invalid_argument.
void setRefineOption(refine::RefineOptions& options, const std::string& key_value);

class FramePoseRefinement
{
   public:
    explicit FramePoseRefinement(refine::RefineOptions options);
    /// The pose to integrate the frame at; `map` may be null (no map yet: the external pose,
    /// counted as too few points).
    Pose refine(const PanopticMap* map, const PanopticFrame& frame, const Pose& T_world_cam_external, double t);
    const refine::PoseRefiner& refiner() const { return refiner_; }
    /// The camera / localiser time offset seen so far (refined vs external poses).
    refine::TimeOffsetEstimate timeOffset() const { return time_offset_.estimate(); }
    /// t, pose (TUM: timestamp tx ty tz qx qy qz qw), one line per frame; the time offset
    /// estimate in a comment line at the top.
    void writeTum(const std::string& path) const;
    size_t size() const { return poses_.size(); }

   private:
    refine::PoseRefiner refiner_;
    refine::TimeOffsetEstimator time_offset_;
    std::vector<std::pair<double, Pose>> poses_;
};

}  // namespace pndt::app
