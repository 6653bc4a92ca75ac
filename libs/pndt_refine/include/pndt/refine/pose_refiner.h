// Frame-to-map pose refinement (issue #22): before a frame is integrated, its points
// are registered to the map's NDT Gaussians, warm-started at the external pose (times
// the correction carried from earlier frames). Point-to-distribution cost with a robust
// loss, 6-DoF on SE(3) (unit quaternion manifold + translation), solved with Ceres.
// Safety: the correction per frame and accumulated over frames is bounded; a degenerate
// (e.g. a single plane, too few Gaussians) or non-converged solve falls back and is
// counted. Pure algorithm: no I/O; Ceres stays a private dependency.
#pragma once

#include <pndt/frame.h>
#include <pndt/panoptic_map.h>
#include <pndt/types.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace pndt::refine
{
enum class RobustLoss
{
    Cauchy,
    Huber,
    None,
};

/// Why a frame kept its unrefined pose (or Accepted).
enum class Outcome
{
    Accepted,
    Disabled,         ///< options.enabled = false
    TooFewPoints,     ///< fewer than min_points frame points found a map Gaussian (an empty map: the first frame)
    Degenerate,       ///< the cost does not constrain all 6 DoF (a single plane, a corridor)
    NotConverged,     ///< Ceres did not converge or failed
    StepTooLarge,     ///< the correction of this frame exceeded max_step_*
    DriftTooLarge,    ///< the accumulated correction exceeded max_total_*
};
const char* outcomeName(Outcome o);

struct RefineOptions
{
    bool enabled = false;
    // ---- points
    double subsample_voxel = 0.0;   ///< one frame point (nearest the centre) per cube of this edge (0: half the map's voxel size)
    int pixel_step = 2;             ///< every n-th pixel in rows and columns is read
    uint32_t max_points = 1500;     ///< at most this many subsampled points (evenly thinned)
    double max_depth = 6.0;         ///< metres; farther points are not used
    // ---- cost
    RobustLoss loss = RobustLoss::Cauchy;
    double loss_scale = 1.0;        ///< robust loss scale on the Mahalanobis distance (sigmas)
    double gate_sigma = 2.0;        ///< associations farther than this many sigmas are dropped
    /// The map's covariances get at least this std-dev (fraction of the voxel size) for
    /// registration: a wider basin than the map's own floor (ndt_min_sigma_ratio).
    double min_sigma_ratio = 0.2;
    /// Map voxels with fewer NDT samples than this (or than the map's ndt_min_samples) are not used.
    uint32_t min_samples = 20;
    /// After convergence, one more solve with this floor (0: none), closer to the surfaces.
    double fine_sigma_ratio = 0.05;
    /// Residual weights per semantic class: stuff (wall, floor, ceiling) is trusted,
    /// things (movable) less; overrides by class id. Void / unlabelled pixels: void_weight.
    double stuff_weight = 1.0;
    double thing_weight = 0.5;
    double void_weight = 1.0;
    std::vector<std::pair<uint16_t, double>> class_weights;
    // ---- solver
    int outer_iterations = 10;      ///< re-associations
    int max_iterations = 20;        ///< Ceres iterations per association
    uint32_t min_points = 150;      ///< associated points needed to try
    /// Degeneracy: smallest / largest eigenvalue of the normalised 6x6 information
    /// (rotation scaled by the points' RMS radius) must reach this.
    double min_eigen_ratio = 0.02;
    // ---- safety
    double max_step_translation = 0.10;  ///< metres per frame (against the warm start)
    double max_step_rotation = 0.05;     ///< radians per frame
    double max_total_translation = 0.5;  ///< metres of accumulated correction (against the external pose)
    double max_total_rotation = 0.2;     ///< radians
    /// Carry the last accepted correction to the next frame's warm start (drift is smooth).
    bool carry_correction = true;
    /// A refused frame is integrated at the carried pose (true) or the bare external pose.
    bool fallback_keeps_correction = true;

    /// Throws std::invalid_argument naming the first bad value.
    void validate() const;
};

/// One refine() call.
struct RefineResult
{
    Outcome outcome = Outcome::Disabled;
    Pose pose = Pose::Identity();         ///< the pose to integrate the frame at
    Pose warm_start = Pose::Identity();   ///< external pose with the carried correction
    Pose correction = Pose::Identity();   ///< pose * external^-1 (world frame), what is carried
    uint32_t points = 0;                  ///< subsampled frame points
    uint32_t associated = 0;              ///< of those with a map Gaussian (last association)
    int iterations = 0;                   ///< Ceres iterations, all associations
    double initial_cost = 0, final_cost = 0;
    double eigen_ratio = 0;               ///< degeneracy measure (see min_eigen_ratio)
    double step_translation = 0, step_rotation = 0;  ///< refined vs warm start
    double seconds = 0;
    bool accepted() const { return outcome == Outcome::Accepted; }
};

/// Counts over a run.
struct RefineStats
{
    uint64_t frames = 0;
    std::array<uint64_t, 7> by_outcome{};  ///< indexed by Outcome
    double seconds = 0;
    uint64_t accepted() const { return by_outcome[size_t(Outcome::Accepted)]; }
    /// Frames that were tried and fell back (not Disabled, not Accepted).
    uint64_t fallbacks() const { return frames - accepted() - by_outcome[size_t(Outcome::Disabled)]; }
    std::string summary() const;
};

/// Refines frame poses against a map. Keeps the carried correction between frames and
/// scratch buffers reused from frame to frame (no per-frame allocation besides Ceres's).
/// One refiner per frame stream; not thread-safe.
class PoseRefiner
{
   public:
    explicit PoseRefiner(RefineOptions options = {});
    ~PoseRefiner();
    PoseRefiner(PoseRefiner&&) noexcept;
    PoseRefiner& operator=(PoseRefiner&&) noexcept;

    const RefineOptions& options() const { return options_; }

    /// The pose to integrate `frame` at: the frame registered to `map`, warm-started at
    /// correction() * T_world_cam_external; on refusal the fallback pose (see options).
    RefineResult refine(const PanopticMap& map, const PanopticFrame& frame, const Pose& T_world_cam_external);
    /// The same over the caller's buffers (uint16 or float depth, z or ray length, strides;
    /// nothing copied).
    RefineResult refine(const PanopticMap& map, const FrameView& frame, const Pose& T_world_cam_external);

    /// The world-frame correction carried to the next frame (identity at the start).
    const Pose& correction() const { return correction_; }
    void setCorrection(const Pose& c) { correction_ = c; }
    void reset();
    const RefineStats& stats() const { return stats_; }

   private:
    struct Impl;
    RefineOptions options_;
    Pose correction_ = Pose::Identity();
    RefineStats stats_;
    std::unique_ptr<Impl> impl_;
};

/// Trajectory errors (Sturm et al., TUM RGB-D benchmark) of `estimate` against `truth`
/// (same length, frame by frame). ATE: RMSE of positions after the best rigid alignment
/// (Horn) when `align`, else as given; RPE: RMSE of the relative motion error over `delta` frames.
struct TrajectoryError
{
    double ate_rmse = 0;           ///< metres
    double rpe_translation = 0;    ///< metres per `delta` frames, RMSE
    double rpe_rotation = 0;       ///< radians per `delta` frames, RMSE
};
TrajectoryError trajectoryError(const std::vector<Pose>& estimate, const std::vector<Pose>& truth, bool align = true,
                                int delta = 1);

}  // namespace pndt::refine
