// Orbit camera paths.
#include "pndt/sim/trajectory.h"

#include <cmath>

namespace pndt::sim
{
std::vector<Pose> orbit(const Eigen::Vector3d& center, double radius, double eye_height,
                        double target_height, int n_frames, double start_angle_rad,
                        double sweep_rad)
{
    if (!(radius > 0)) throw InputError("orbit: radius must be positive");
    if (n_frames < 0) throw InputError("orbit: negative number of frames");
    std::vector<Pose> poses;
    poses.reserve(static_cast<size_t>(n_frames));
    const bool closed = std::abs(sweep_rad) >= kTwoPi;
    const double step =
        closed ? sweep_rad / n_frames : (n_frames > 1 ? sweep_rad / (n_frames - 1) : 0.0);
    const Eigen::Vector3d target(center.x(), center.y(), center.z() + target_height);
    for (int i = 0; i < n_frames; ++i)
    {
        const double a = start_angle_rad + i * step;
        const Eigen::Vector3d eye(center.x() + radius * std::cos(a),
                                  center.y() + radius * std::sin(a), center.z() + eye_height);
        poses.push_back(lookAt(eye, target));
    }
    return poses;
}

}  // namespace pndt::sim
