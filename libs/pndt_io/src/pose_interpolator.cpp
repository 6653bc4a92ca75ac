#include <pndt/io/pose_interpolator.h>

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <cmath>

namespace pndt::io
{
PoseInterpolator::PoseInterpolator(std::vector<StampedPose> poses)
{
    poses_.reserve(poses.size());
    quats_.reserve(poses.size());
    for (const StampedPose& p : poses) append(p);
}

void PoseInterpolator::append(const StampedPose& pose)
{
    const size_t i = forgotten_ + poses_.size();
    const double t = pose.t;
    if (!std::isfinite(t)) throw InputError(fmt::format("PoseInterpolator: pose {} has a non-finite stamp", i));
    if (!poses_.empty() && !(t > poses_.back().t))
        throw InputError(fmt::format(
            "PoseInterpolator: pose {} (t={:.9f}) is {} pose {} (t={:.9f}); stamps must be "
            "strictly increasing",
            i, t, t == poses_.back().t ? "a duplicate stamp of" : "out of order, before", i - 1, poses_.back().t));
    poses_.push_back(pose);
    quats_.emplace_back(pose.T_world_sensor.rotation());
    quats_.back().normalize();
}

void PoseInterpolator::forgetBefore(double t)
{
    // Poses [0, drop) lie before the last stamp <= t: at() never brackets a time >= t with them.
    const auto first_after = std::upper_bound(poses_.begin(), poses_.end(), t,
                                              [](double v, const StampedPose& p) { return v < p.t; });
    if (first_after == poses_.begin()) return;
    const size_t drop = size_t(first_after - poses_.begin()) - 1;
    if (drop < 1024 || drop < poses_.size() - drop) return;  // each pose moves O(1) times on average
    poses_.erase(poses_.begin(), poses_.begin() + std::ptrdiff_t(drop));
    quats_.erase(quats_.begin(), quats_.begin() + std::ptrdiff_t(drop));
    forgotten_ += drop;
}

double PoseInterpolator::startTime() const
{
    if (poses_.empty()) throw InputError("PoseInterpolator: empty trajectory");
    return poses_.front().t;
}

double PoseInterpolator::endTime() const
{
    if (poses_.empty()) throw InputError("PoseInterpolator: empty trajectory");
    return poses_.back().t;
}

std::optional<Pose> PoseInterpolator::at(double t, double max_gap) const
{
    if (poses_.empty() || !std::isfinite(t)) return std::nullopt;
    if (t < poses_.front().t || t > poses_.back().t) return std::nullopt;
    // First stored stamp >= t.
    auto it = std::lower_bound(poses_.begin(), poses_.end(), t,
                               [](const StampedPose& p, double v) { return p.t < v; });
    const size_t hi = static_cast<size_t>(it - poses_.begin());
    if (poses_[hi].t == t) return poses_[hi].T_world_sensor;
    const size_t lo = hi - 1;  // hi > 0 because t > front().t here
    const double gap = poses_[hi].t - poses_[lo].t;
    // Stamps near 1e9 s carry ~1e-7 s of rounding: 10 Hz poses must pass max_gap = 0.1.
    // Allow a thousand ulps of the stamp (0.3 ms at 1.3e9 s).
    const double slack = 1e3 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(poses_[hi].t));
    if (!(gap <= max_gap + slack)) return std::nullopt;
    const double alpha = (t - poses_[lo].t) / gap;
    Pose out = Pose::Identity();
    out.linear() = quats_[lo].slerp(alpha, quats_[hi]).toRotationMatrix();
    out.translation() = (1.0 - alpha) * poses_[lo].T_world_sensor.translation() +
                        alpha * poses_[hi].T_world_sensor.translation();
    return out;
}

Pose interpolatePose(const Pose& a, const Pose& b, double alpha)
{
    Eigen::Quaterniond qa(a.rotation()), qb(b.rotation());
    qa.normalize();
    qb.normalize();
    Pose out = Pose::Identity();
    out.linear() = qa.slerp(alpha, qb).toRotationMatrix();
    out.translation() = (1.0 - alpha) * a.translation() + alpha * b.translation();
    return out;
}

}  // namespace pndt::io
