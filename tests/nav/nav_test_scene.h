// The navigation tests' scene: an 8 x 6 x 2.6 m room with table A (1.6 x 0.9 m at
// (-1.83, 0.04), six chairs around it) and table B (1.2 x 0.8 m at (1.93, 0.27), three
// chairs and a lamp on it), mapped at 10 cm from ground-truth labels (score 0.9).
// Built once per test program; also saved to a .pndt.gz and loaded back so every
// test can run on both.
#pragma once

#include <pndt/mrpt/PanopticNDTMap.h>
#include <pndt/sim/scene.h>

#include <string>
#include <vector>

namespace navtest
{
struct ObjectTruth
{
    std::string name;      ///< "table A", "chair A1", ...
    uint16_t semantic = 0;
    Eigen::Vector2d xy;    ///< footprint centre
    Eigen::Vector2d half;  ///< footprint half sizes (axis-aligned)
    double height = 0;
};

constexpr double kRoomHalfX = 4.0, kRoomHalfY = 3.0, kRoomHeight = 2.6;
// Off the 10 cm voxel grid on purpose: edges on cell borders would make
// "which cell is the edge in" a coin toss.
const Eigen::Vector2d kTableA(-1.83, 0.04), kTableB(1.93, 0.27);

const pndt::sim::Scene& scene();
/// Ground truth of the furniture, tables first.
const std::vector<ObjectTruth>& truth();

/// The frames' camera poses and the camera.
std::vector<pndt::Pose> cameraPoses();
pndt::CameraIntrinsics camera();
/// A rendered frame with ground-truth labels, scores 0.9.
pndt::PanopticFrame renderFrame(const pndt::Pose& T_world_cam);

/// The map built from all frames (built once).
const pndt::PanopticNDTMap& builtMap();
/// The same map written to a temporary .pndt.gz and read back (once); its path.
const pndt::PanopticNDTMap& loadedMap();
const std::string& savedMapPath();

/// The same frames with network-like labels (pndt_data's segmentation noise model,
/// strength 1: whole objects confused, split, merged or missed, as EMSANet does).
pndt::PanopticFrame renderNoisyFrame(const pndt::Pose& T_world_cam, uint64_t frame_index);
const pndt::PanopticNDTMap& noisyMap();

/// builtMap(), loadedMap() or noisyMap() ("built", "loaded", "noisy"), for parameterised tests.
const pndt::PanopticNDTMap& mapNamed(const std::string& which);

}  // namespace navtest
