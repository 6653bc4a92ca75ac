// Instance masks of detector boxes from the depth image (internal to the detector front-end).
#pragma once

#include <pndt/seg/detector_geometry.h>

#include <vector>

namespace pndt::seg
{
/// Grows the connected depth segment of a box: seeded at the median depth of a small window at
/// the box centre (3x3 .. 9x9, growing with the box) when more than half of it is free valid
/// depth, else of the free valid pixels of the box's central third, else of its free and
/// `claimable` ones; 4-connected inside the box, across neighbours whose depth differs by less
/// than z · max(depth_step, footprints / focal). Pixels are free when owner[i] is 0 or
/// `claimable` (wall: a picture or a TV on a wall is nearly coplanar with it); every other owner
/// (floor, ceiling, a higher-scored instance) is never taken. Writes `id` into owner for the
/// mask's pixels and returns its size; a mask smaller than min_share of the box is undone
/// (returns 0). Images up to 65535 pixels a side (pixels are queued as packed x, y).
class BoxMaskGrower
{
   public:
    size_t grow(const Image<float>& depth, const Detection& box, uint32_t id, double depth_step, double footprints,
                double focal, double min_share, uint32_t claimable, std::vector<uint32_t>& owner);

    /// The pixels (indices into the image) of the last mask grow() kept.
    const std::vector<int>& pixels() const { return queue_; }

   private:
    /// Pixel index of the box's seed, −1 if it has no usable pixel.
    int findSeed(const Image<float>& depth, int x0, int y0, int x1, int y1, uint32_t claimable,
                 const std::vector<uint32_t>& owner);
    /// The valid pixel of [x0, x1) × [y0, y1) owned by 0 or `claimable` whose depth is nearest
    /// to their median (first in raster order); −1 if there is none.
    int medianPixel(const Image<float>& depth, int x0, int y0, int x1, int y1, uint32_t claimable,
                    const std::vector<uint32_t>& owner);

    std::vector<float> window_;
    std::vector<uint32_t> frontier_;  ///< the mask's pixels as x | y << 16, in visiting order
    std::vector<int> queue_;          ///< the kept mask's pixel indices
    std::vector<uint32_t> previous_;  ///< owner of each queued pixel before, to undo a dropped mask
};

}  // namespace pndt::seg
