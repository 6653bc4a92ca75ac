// Instance masks of detector boxes from the depth image (internal to the detector front-end).
#pragma once

#include <pndt/seg/detector_geometry.h>

#include <vector>

namespace pndt::seg
{
/// Grows the connected depth segment of a box: seeded at the median depth of the box's central
/// third (non-stuff, valid pixels), 4-connected inside the box, across neighbours whose depth
/// differs by less than z · max(depth_step, footprints / focal). Pixels are free when owner[i] is 0 or `claimable` (wall:
/// a picture or a TV on a wall is nearly coplanar with it); every other owner (floor, ceiling, a
/// higher-scored instance) is never taken. Writes `id` into owner for the mask's pixels and
/// returns its size; a mask smaller than min_share of the box is undone (returns 0).
class BoxMaskGrower
{
   public:
    size_t grow(const Image<float>& depth, const Detection& box, uint32_t id, double depth_step, double footprints,
                double focal, double min_share, uint32_t claimable, std::vector<uint32_t>& owner);

   private:
    std::vector<float> window_;
    std::vector<int> queue_;
    std::vector<uint32_t> previous_;  ///< owner of each queued pixel before, to undo a dropped mask
};

}  // namespace pndt::seg
