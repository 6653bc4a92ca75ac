// Query: the map rendered into a pinhole camera (2D evaluation, PNG views).
#include <pndt/ray_walk.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "map_scratch.h"

namespace pndt
{
namespace
{
/// Ray parameter where o + t*d enters the axis-aligned box [lo, lo+size].
double boxEntry(const Eigen::Vector3d& lo, double size, const Eigen::Vector3d& o, const Eigen::Vector3d& d)
{
    double t_enter = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i)
    {
        if (d[i] == 0) continue;
        const double t0 = (lo[i] - o[i]) / d[i], t1 = (lo[i] + size - o[i]) / d[i];
        t_enter = std::max(t_enter, std::min(t0, t1));
    }
    return std::max(t_enter, 0.0);
}
}  // namespace

void PanopticMap::render(const Pose& T_world_cam, const CameraIntrinsics& K, RenderedView& out) const
{
    // As integrate() checks them: a focal length of 0 walked endless rays.
    if (const std::string problem = K.invalidReason(); !problem.empty())
        throw InputError("render: invalid camera intrinsics: " + problem);
    if (size_t(K.width) * size_t(K.height) >= (size_t(1) << 25))
        throw InputError("render: a " + std::to_string(K.width) + "x" + std::to_string(K.height) +
                         " image is too large (at most 2^25 pixels)");
    if (const std::string problem = poseInvalidReason(T_world_cam); !problem.empty()) throw InputError("render: " + problem);
    ensurePropagated();
    out.depth.resize(K.width, K.height, 0.f);
    out.semantic.resize(K.width, K.height, 0);
    out.panoptic_semantic.resize(K.width, K.height, 0);
    out.instance.resize(K.width, K.height, 0);
    const Eigen::Matrix3d R = T_world_cam.linear();
    const Eigen::Vector3d o = T_world_cam.translation();
    const double max_depth = options_.max_range;
    const bool ndt = options_.use_ndt;

    for (int r = 0; r < K.height; ++r)
        for (int c = 0; c < K.width; ++c)
        {
            // Direction with unit optical-axis component: its parameter t is the depth.
            const Eigen::Vector3d d = R * Eigen::Vector3d((c - K.cx) / K.fx, (r - K.cy) / K.fy, 1.0);
            double depth = 0;
            uint32_t hit = kNoRecord;
            walkSegment(grid_, o, o + d * max_depth, [&](const VoxelKey& k) {
                const uint32_t vi = store_.find(k);
                if (vi == kNoRecord) return true;
                const Voxel& v = store_[vi];
                if (!isOccupied(v)) return true;
                if (ndt && hasGaussian(v))
                {
                    // Hit where the ray is most likely under the voxel's Gaussian.
                    const NdtGaussian g = gaussianOf(v);
                    const double t = maxLikelihoodOnLine(g, o, d);
                    if (t <= 0 || g.mahalanobisSq(o + t * d) > options_.query_mahalanobis_sq) return true;
                    depth = t;
                }
                else
                    depth = boxEntry(grid_.minCorner(k), grid_.voxelSize(), o, d);
                hit = vi;
                return false;
            });
            if (hit == kNoRecord) continue;
            const size_t i = size_t(r) * K.width + c;
            out.depth.data[i] = float(depth);
            out.semantic.data[i] = semanticLabel(hit);
            const PanopticLabel pl = panopticLabel(hit);
            out.panoptic_semantic.data[i] = pl.semantic;
            out.instance.data[i] = pl.instance;
        }
}

}  // namespace pndt
