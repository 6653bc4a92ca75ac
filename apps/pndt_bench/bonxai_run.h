// Bonxai (facontidavide/Bonxai, a VDB-like grid; not in Debian) on the bench's
// frames, occupancy only: built only when the bench is configured with
// -DPNDT_BONXAI_DIR=<a Bonxai source tree> (benchmark only, never vendored).
#pragma once

#include "occupancy_run.h"

namespace pndt::bench
{
/// Whether this build has Bonxai.
bool haveBonxai();
/// Bonxai's ProbabilisticMap::insertPointCloud with every frame's world points
/// from the camera position, `max_range` as for OctoMap (one hit per voxel and
/// frame, a ray to each hit voxel: like OctoMap's lazy_eval + discretize).
OccupancyRun runBonxai(const BenchFrames& b, double voxel, double max_range);
}  // namespace pndt::bench
