#include <fmt/format.h>
#include <pndt/seg/detector_geometry.h>

#include <algorithm>
#include <cmath>

#include "box_masks.h"
#include "depth_planes.h"

namespace pndt::seg
{
struct DetectorGeometryLabeller::Work
{
    explicit Work(const GeometryLabelOptions& o) : planes(o) {}
    PlaneFinder planes;
    BoxMaskGrower masks;
    std::vector<uint32_t> owner;  ///< 0 free, kStuff, else detection rank + 1
    std::vector<size_t> order;
};

namespace
{
constexpr uint32_t kStuff = 0xFFFFFFFFu;  ///< floor / ceiling: never part of a thing
constexpr uint32_t kWall = 0xFFFFFFFEu;   ///< wall: a thing's mask may take it (a TV on the wall)
}

DetectorGeometryLabeller::DetectorGeometryLabeller(const ClassSet& classes, std::vector<uint16_t> detector_to_class,
                                                   GeometryLabelOptions options)
    : classes_(classes),
      detector_to_class_(std::move(detector_to_class)),
      options_(options),
      work_(std::make_unique<Work>(options_))
{
    for (uint16_t c : detector_to_class_)
        if (!classes_.contains(c))
            throw InputError(fmt::format("detector labeller: class id {} is outside the class set", c));
    floor_ = std::max(0, classes_.find("floor"));
    ceiling_ = std::max(0, classes_.find("ceiling"));
    wall_ = std::max(0, classes_.find("wall"));
}

DetectorGeometryLabeller::~DetectorGeometryLabeller() = default;

GeometryLabelStats DetectorGeometryLabeller::label(const Image<float>& depth, const CameraIntrinsics& K,
                                                   const Eigen::Vector3d& up_cam,
                                                   const std::vector<Detection>& detections, PanopticFrame& out)
{
    if (K.width != depth.width || K.height != depth.height)
        throw InputError(fmt::format("detector labeller: depth image is {}x{} but the intrinsics are for {}x{}",
                                     depth.width, depth.height, K.width, K.height));
    if (!up_cam.allFinite() || up_cam.norm() < 1e-9) throw InputError("detector labeller: gravity 'up' is not a direction");
    const int W = depth.width, H = depth.height;
    const size_t N = size_t(W) * H;
    GeometryLabelStats stats;
    out.semantic.resize(W, H, 0);
    out.semantic_score.resize(W, H, 0.f);
    out.instance.resize(W, H, 0);
    out.panoptic_score.resize(W, H, 0.f);
    auto& owner = work_->owner;
    owner.assign(N, 0);

    // Stuff: every valid pixel near a structural plane (the nearest one within tolerance).
    const auto& planes = work_->planes.find(depth, K, up_cam);
    for (const auto& p : planes)
        (p.kind == PlaneKind::Floor ? stats.planes_floor : p.kind == PlaneKind::Ceiling ? stats.planes_ceiling
                                                                                       : stats.planes_wall)++;
    if (!planes.empty())
        for (int r = 0; r < H; ++r)
            for (int c = 0; c < W; ++c)
            {
                const float z = depth.at(r, c);
                if (!(z > 0) || !std::isfinite(z)) continue;
                const Eigen::Vector3f P = K.unproject(c, r, z).cast<float>();
                const float tol = work_->planes.tolerance(z);
                float best = 1.f;
                const StructuralPlane* on = nullptr;
                for (const auto& p : planes)
                {
                    const float rel = std::abs(p.n.dot(P) + p.d) / tol;
                    if (rel < best && work_->planes.nearRegion(p, r, c))
                    {
                        best = rel;
                        on = &p;
                    }
                }
                if (!on) continue;
                const int cls = on->kind == PlaneKind::Floor ? floor_ : on->kind == PlaneKind::Ceiling ? ceiling_ : wall_;
                if (cls == 0) continue;
                const size_t i = size_t(r) * W + c;
                owner[i] = on->kind == PlaneKind::Wall ? kWall : kStuff;
                out.semantic.data[i] = uint16_t(cls);
                out.semantic_score.data[i] = on->gravity_agreement * (1.f - 0.5f * best * best);
            }

    // Things: detections in score order, each the depth segment of its box; higher scores first
    // so that where masks would overlap the higher score owns the pixel.
    auto& order = work_->order;
    order.resize(detections.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return detections[a].score > detections[b].score; });
    uint32_t next_id = 1;
    for (size_t k : order)
    {
        const Detection& d = detections[k];
        const uint16_t cls = d.model_class >= 0 && size_t(d.model_class) < detector_to_class_.size()
                                 ? detector_to_class_[size_t(d.model_class)]
                                 : 0;
        if (cls == 0 || !(d.score > 0))
        {
            ++stats.detections_dropped;
            continue;
        }
        const uint32_t id = next_id;
        if (work_->masks.grow(depth, d, id, options_.segment_depth_step, options_.segment_footprints,
                              0.5 * (K.fx + K.fy), options_.min_mask_share, kWall, owner) == 0)
        {
            ++stats.detections_dropped;
            continue;
        }
        ++next_id;
        ++stats.detections_used;
        const float s = std::min(d.score, 1.f);
        const int x0 = std::max(0, int(std::floor(d.x0))), x1 = std::min(W, int(std::ceil(d.x1)));
        const int y0 = std::max(0, int(std::floor(d.y0))), y1 = std::min(H, int(std::ceil(d.y1)));
        for (int r = y0; r < y1; ++r)
            for (int c = x0; c < x1; ++c)
            {
                const size_t i = size_t(r) * W + c;
                if (owner[i] != id) continue;
                out.semantic.data[i] = cls;
                out.semantic_score.data[i] = s;
                out.instance.data[i] = id;
                out.panoptic_score.data[i] = s * s;
            }
    }
    return stats;
}

}  // namespace pndt::seg
