// Estimate of a constant time offset between the camera's and the localiser's clocks
// (issue #22), from what the pose refinement sees: per frame the camera stamp t, the
// external pose E(t) it was given and, when the refinement was accepted, the refined pose.
// If the localiser's poses belong δ later than their stamps say (the true pose at camera
// time t is E(t + δ)), a refined trajectory that follows the truth differs from E(t) by
// about δ·v(t) (v the external velocity) plus a slowly changing correction (the drift). The
// estimate fits r_i = P_i − E(t_i + δ) ≈ c_w + (δ* − δ)·v_i by least squares in δ, with an
// own constant c_w (optionally a line) per time window (drift), and iterates (Gauss-Newton on δ). Positions
// only. Needs motion that changes velocity within a window: a straight line at constant
// speed cannot tell a time offset from a position offset (reported as not observable).
// Pure algorithm, no I/O.
#pragma once

#include <pndt/types.h>

#include <string>
#include <vector>

namespace pndt::refine
{
struct TimeOffsetOptions
{
    double window_seconds = 1.0;   ///< each window gets its own position offset (drift)
    /// Each window also gets its own drift rate (a line in time per axis): less bias from
    /// drift and from the refinement's own slow errors, but the part of δ·v that is linear in
    /// time is removed with it (motion must change within a window). Chosen on the Redwood
    /// sample without pose noise: 1.5 / 51.4 ms for true offsets 0 / 50 ms (2 s windows
    /// without lines: -5.7 / 44.2 ms).
    bool detrend = true;
    double max_offset = 0.5;       ///< seconds; an estimate beyond is refused
    size_t min_frames = 20;        ///< accepted frames needed
    double max_standard_error = 0.01;  ///< seconds; a looser estimate is reported as not observable
};

struct TimeOffsetEstimate
{
    bool valid = false;
    /// δ: the camera frame stamped t matches the localiser's pose stamped t + δ. To line them
    /// up, add −δ to the pose stamps (pndt-live --clock-offset, which is added to pose stamps).
    double offset = 0;
    double standard_error = 0;  ///< seconds (1 σ, from the fit's residuals)
    double rms_before = 0;      ///< metres: refined vs external positions (window intercepts removed) at δ = 0
    double rms_after = 0;       ///< the same at δ
    size_t frames = 0;          ///< accepted frames used
    std::string reason;         ///< why not valid
    std::string summary() const;
};

class TimeOffsetEstimator
{
   public:
    explicit TimeOffsetEstimator(TimeOffsetOptions options = {}) : options_(options) {}
    /// One frame in stamp order: its camera stamp, the external pose used, the refined pose,
    /// whether the refinement was accepted (others only carry the external trajectory).
    void add(double t, const Pose& external, const Pose& refined, bool accepted);
    TimeOffsetEstimate estimate() const;
    size_t size() const { return t_.size(); }
    void clear();

   private:
    TimeOffsetOptions options_;
    std::vector<double> t_;
    std::vector<Eigen::Vector3d> external_, refined_;
    std::vector<char> accepted_;
};

}  // namespace pndt::refine
