// Camera poses for synthetic sequences (optical convention: x right, y down, z forward).
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "pndt/look_at.h"
#include "pndt/types.h"

namespace pndt::sim
{
constexpr double kTwoPi = 6.283185307179586476925286766559;

/// pndt::lookAt (pndt/look_at.h), where synthetic sequences have always found it.
using pndt::lookAt;

/// `n_frames` poses on a horizontal circle of `radius` around `center`, each looking at
/// the circle's axis. Heights are relative to center.z(): eye at center.z() + eye_height,
/// target (center.x(), center.y(), center.z() + target_height). Frame i is at angle
/// start_angle_rad + i * step, counter-clockwise about +z; for a full turn
/// (|sweep_rad| >= 2 pi) step = sweep_rad / n_frames (a closed loop without a repeated
/// frame), otherwise step = sweep_rad / (n_frames - 1) (both ends included).
/// Throws InputError for radius <= 0 or n_frames < 0.
std::vector<Pose> orbit(const Eigen::Vector3d& center, double radius, double eye_height,
                        double target_height, int n_frames, double start_angle_rad = 0,
                        double sweep_rad = kTwoPi);

}  // namespace pndt::sim
