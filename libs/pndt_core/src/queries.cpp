// Query: the label at a world point (3D evaluation, object lookup).
#include <limits>

#include "map_scratch.h"

namespace pndt
{
PointLabel PanopticMap::labelAt(const Eigen::Vector3d& p) const
{
    ensurePropagated();
    PointLabel best;
    if (!grid_.holds(p)) return best;  // NaN or far away: no voxel (a likelihood's floor, not a hit)
    const VoxelKey k0 = grid_.keyOf(p);
    if (options_.use_ndt)
    {
        // Own voxel and its 26 neighbours: the Gaussian nearest in Mahalanobis distance.
        best.mahalanobis_sq = std::numeric_limits<double>::infinity();
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                {
                    const uint32_t vi = store_.find({k0.x + dx, k0.y + dy, k0.z + dz});
                    if (vi == kNoRecord) continue;
                    const Voxel& v = store_[vi];
                    if (!isOccupied(v) || !hasGaussian(v)) continue;
                    const double m2 = gaussianOf(v).mahalanobisSq(p);
                    if (m2 <= best.mahalanobis_sq)
                    {
                        best.found = true;
                        best.voxel = vi;
                        best.mahalanobis_sq = m2;
                    }
                }
    }
    if (!best.found)
    {
        // Cube ablation, or no usable Gaussian nearby: the containing voxel.
        const uint32_t vi = store_.find(k0);
        if (vi != kNoRecord && isOccupied(store_[vi]))
        {
            best.found = true;
            best.voxel = vi;
            best.mahalanobis_sq = 0;
        }
    }
    if (best.found)
    {
        best.semantic = semanticLabel(best.voxel);
        best.panoptic = panopticLabel(best.voxel);
    }
    return best;
}

}  // namespace pndt
