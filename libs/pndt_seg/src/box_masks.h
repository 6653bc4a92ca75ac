// Instance masks of detector boxes from the depth image (internal to the detector front-end).
#pragma once

#include <pndt/seg/detector_geometry.h>

#include <vector>

namespace pndt::seg
{
/// Grows the connected depth segment of a box: seeded at the median depth of the box's central
/// third (non-stuff, valid pixels), 4-connected inside the box, across neighbours whose depth
/// differs by less than depth_step × z. Pixels with owner[i] != 0 (stuff, or a higher-scored
/// instance) are never taken. Writes `id` into owner for the mask's pixels and returns its size;
/// a mask smaller than min_share of the box is undone (returns 0).
class BoxMaskGrower
{
   public:
    size_t grow(const Image<float>& depth, const Detection& box, uint32_t id, double depth_step, double min_share,
                std::vector<uint32_t>& owner);

   private:
    std::vector<float> window_;
    std::vector<int> queue_;
};

}  // namespace pndt::seg
