// The obstacle points PanopticNDTMap::getAsSimplePointsMap() hands out, kept
// until the map or the options change (a reactive navigator asks every step).
#pragma once

#include <mrpt/maps/CSimplePointsMap.h>
#include <pndt/mrpt/obstacle_points.h>

#include <cstdint>

namespace pndt
{
class ObstacleCache
{
   public:
    ObstacleCache() = default;
    /// A copy starts empty: the points belong to the map they were made from.
    ObstacleCache(const ObstacleCache&) {}
    ObstacleCache& operator=(const ObstacleCache&)
    {
        invalidate();
        return *this;
    }

    /// The map's obstacle points for `o`; recomputed when the map changed (its
    /// fingerprint: voxel and record counts and the sum of all log-odds) or `o` did.
    const mrpt::maps::CSimplePointsMap& get(const PanopticMap& map, const ObstacleOptions& o);
    void invalidate() { valid_ = false; }
    /// How often the points were computed (for tests).
    uint64_t computations() const { return computations_; }

   private:
    mrpt::maps::CSimplePointsMap points_;
    ObstacleOptions options_;
    uint64_t fingerprint_ = 0;
    bool valid_ = false;
    uint64_t computations_ = 0;
};

/// A cheap summary that changes whenever the map's occupancy does.
uint64_t mapFingerprint(const PanopticMap& map);

}  // namespace pndt
