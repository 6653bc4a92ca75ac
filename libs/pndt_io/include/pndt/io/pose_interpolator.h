// Pose lookup at arbitrary times from a time-sorted trajectory.
#pragma once

#include <pndt/io/poses.h>

#include <optional>
#include <vector>

namespace pndt::io
{
/// Interpolates a trajectory: linear in translation, quaternion SLERP (shortest arc) in rotation,
/// between the two stored poses that bracket the query time.
class PoseInterpolator
{
public:
    PoseInterpolator() = default;
    /// Throws InputError naming the index if a stamp is non-finite or not strictly greater than
    /// its predecessor (out of order or duplicated).
    explicit PoseInterpolator(std::vector<StampedPose> poses);
    /// Adds a pose after the last one (poses read while mapping); the same checks.
    void append(const StampedPose& pose);

    /// Pose at time t:
    ///  * exact hit on a stored stamp → that stored pose (max_gap does not matter);
    ///  * std::nullopt if t is outside [first stamp, last stamp] or not finite;
    ///  * std::nullopt if the two bracketing stamps are more than max_gap seconds apart
    ///    (the frame must then be skipped, never mapped with a stale pose).
    std::optional<Pose> at(double t, double max_gap) const;

    /// Lets go of the poses no query at time >= t needs (those before the last stamp <= t), so
    /// that a track fed for hours (a live localiser) stays small; a query before t may then find
    /// no pose. Amortised: the poses are dropped once they are at least 1024 and as many as the
    /// poses kept.
    void forgetBefore(double t);

    bool empty() const { return poses_.empty(); }
    size_t size() const { return poses_.size(); }  ///< poses held (not counting forgotten ones)
    size_t appended() const { return forgotten_ + poses_.size(); }  ///< poses ever appended
    double startTime() const;  ///< throws if empty
    double endTime() const;    ///< throws if empty
    const std::vector<StampedPose>& poses() const { return poses_; }

private:
    std::vector<StampedPose> poses_;
    std::vector<Eigen::Quaterniond> quats_;
    size_t forgotten_ = 0;  ///< poses dropped by forgetBefore (error messages count them)
};

/// SLERP/LERP between two poses, alpha in [0,1] (0 → a, 1 → b).
Pose interpolatePose(const Pose& a, const Pose& b, double alpha);

}  // namespace pndt::io
