// ObstacleCache (obstacle_cache.h).
#include <pndt/mrpt/obstacle_cache.h>

#include <cstring>

namespace pndt
{
uint64_t mapFingerprint(const PanopticMap& map)
{
    const VoxelStore& store = map.voxels();
    double occ_sum = 0;
    for (uint32_t i = 0; i < store.size(); ++i) occ_sum += store[i].occ * double(i % 7 + 1);
    uint64_t bits;
    std::memcpy(&bits, &occ_sum, sizeof bits);
    uint64_t h = bits;
    for (uint64_t n : {uint64_t(store.size()), uint64_t(map.surfaceRecords().size()), uint64_t(map.labelRecords().size()),
                       uint64_t(map.instanceRecords().size())})
        h = (h ^ n) * 0x100000001b3ULL + 0x9e3779b97f4a7c15ULL;
    return h;
}

const mrpt::maps::CSimplePointsMap& ObstacleCache::get(const PanopticMap& map, const ObstacleOptions& o)
{
    const uint64_t f = mapFingerprint(map);
    if (!valid_ || f != fingerprint_ || o != options_)
    {
        obstaclePoints(map, o, points_);
        options_ = o;
        fingerprint_ = f;
        valid_ = true;
        ++computations_;
    }
    return points_;
}

}  // namespace pndt
