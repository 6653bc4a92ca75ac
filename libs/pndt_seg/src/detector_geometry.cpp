#include <fmt/format.h>
#include <pndt/seg/detector_geometry.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "box_masks.h"
#include "depth_planes.h"

namespace pndt::seg
{
namespace
{
constexpr uint32_t kStuff = 0xFFFFFFFFu;  ///< floor / ceiling: never part of a thing
constexpr uint32_t kWall = 0xFFFFFFFEu;   ///< wall: a thing's mask may take it (a TV on the wall)
}  // namespace

struct DetectorGeometryLabeller::Work
{
    explicit Work(const GeometryLabelOptions& o) : planes(o) {}

    /// Every valid pixel in or next to a plane's region and within its tolerance t gets the
    /// nearest such plane's class, S^L = a · (1 − ½ (r / t)²); `owner` marks it as stuff.
    void labelStuff(const Image<float>& depth, const CameraIntrinsics& K, const std::vector<StructuralPlane>& ps,
                    const uint16_t kind_class[3], PanopticFrame& out);

    PlaneFinder planes;
    BoxMaskGrower masks;
    std::vector<uint32_t> owner;  ///< 0 free, kStuff, kWall, else the instance id
    std::vector<size_t> order;
    std::vector<float> ray_x;     ///< (col − cx) / fx per column
    std::vector<float> distance;  ///< per plane, per column of the current row: distance to it
    std::vector<uint32_t> near_px;  ///< per column of the current row: planes near its cell
    std::vector<float> row_best, row_tol, row_inv_tol;  ///< per column: nearest plane's distance, tolerance
    std::vector<int32_t> row_plane;        ///< per column: nearest plane (−1 = none)
    std::vector<uint16_t> plane_class;
    std::vector<uint32_t> plane_owner;
    std::vector<float> plane_agreement;
};

void DetectorGeometryLabeller::Work::labelStuff(const Image<float>& depth, const CameraIntrinsics& K,
                                                const std::vector<StructuralPlane>& ps, const uint16_t kind_class[3],
                                                PanopticFrame& out)
{
    // Distance of pixel (c, r) at depth z to plane k: |z · (n · ray(c, r)) + d| with
    // ray = ((c − cx) / fx, (r − cy) / fy, 1): the x part per column, the rest per row; a row's
    // distances to each plane are computed in one vectorisable loop, then each pixel takes the
    // nearest plane among those whose region is near its cell. Writes every pixel (void if none).
    const int W = depth.width, H = depth.height, step = planes.step();
    const size_t P = ps.size();
    ray_x.resize(size_t(W));
    for (int c = 0; c < W; ++c) ray_x[size_t(c)] = float((c - K.cx) / K.fx);
    distance.resize(P * size_t(W));
    near_px.resize(size_t(W));
    row_best.resize(size_t(W));
    row_tol.resize(size_t(W));
    row_inv_tol.resize(size_t(W));
    row_plane.resize(size_t(W));
    // Per plane: class, owner mark, gravity agreement a (all 0 when the class set lacks it).
    plane_class.assign(P, 0);
    plane_owner.assign(P, 0);
    plane_agreement.assign(P, 0.f);
    for (size_t k = 0; k < P; ++k)
    {
        plane_class[k] = kind_class[int(ps[k].kind)];
        if (plane_class[k] == 0) continue;  // the class set lacks it: the pixel stays void
        plane_owner[k] = ps[k].kind == PlaneKind::Wall ? kWall : kStuff;
        plane_agreement[k] = ps[k].gravity_agreement;
    }
    const float t = float(planes.tolerance(0.f));  // tolerance(z) = t · max(1, z / 2)
    for (int r = 0; r < H; ++r)
    {
        const float ray_y = float((r - K.cy) / K.fy);
        const float* __restrict z_row = &depth.data[size_t(r) * W];
        const float* __restrict rx = ray_x.data();
        for (size_t k = 0; k < P; ++k)
        {
            const float nx = ps[k].n.x(), b = ps[k].n.y() * ray_y + ps[k].n.z(), d = ps[k].d;
            float* __restrict dist = &distance[k * size_t(W)];
            for (int c = 0; c < W; ++c) dist[c] = std::abs(z_row[c] * (nx * rx[c] + b) + d);
        }
        const uint32_t* near = planes.nearRow(r);
        for (int gx = 0, c0 = 0; c0 < W; ++gx, c0 += step)
            for (int c = c0; c < std::min(W, c0 + step); ++c) near_px[size_t(c)] = near[gx];
        // Nearest near plane within tolerance, branch-free over the row (invalid depth: tolerance
        // 0, and NaN distances never compare less).
        float* __restrict best = row_best.data();
        float* __restrict tol = row_tol.data();
        float* __restrict inv_tol = row_inv_tol.data();
        int32_t* __restrict on = row_plane.data();
        for (int c = 0; c < W; ++c)
        {
            const float z = z_row[c];
            tol[c] = z > 0 && z < std::numeric_limits<float>::infinity() ? t * std::max(1.f, 0.5f * z) : 0.f;
            inv_tol[c] = tol[c] > 0 ? 1.f / tol[c] : 0.f;
            best[c] = tol[c];
            on[c] = -1;  // none
        }
        for (size_t k = 0; k < P; ++k)
        {
            const float* __restrict dist = &distance[k * size_t(W)];
            const uint32_t* __restrict bits = near_px.data();
            const uint32_t bit = 1u << k;
            const int32_t id = int32_t(k);
            for (int c = 0; c < W; ++c)
            {
                const float e = dist[c], b = best[c];
                const bool take = (bits[c] & bit) != 0 && e < b;
                best[c] = take ? e : b;
                on[c] = take ? id : on[c];
            }
        }
        uint16_t* __restrict sem = &out.semantic.data[size_t(r) * W];
        float* __restrict score = &out.semantic_score.data[size_t(r) * W];
        uint32_t* __restrict own = &owner[size_t(r) * W];
        for (int c = 0; c < W; ++c)
        {
            sem[c] = 0;
            score[c] = 0.f;
            own[c] = 0;
        }
        for (size_t k = 0; k < P; ++k)
        {
            const int32_t id = int32_t(k);
            const uint16_t cls = plane_class[k];
            const uint32_t mark = plane_owner[k];
            const float a = plane_agreement[k];
            // One output per loop: GCC vectorises each select (not all three in one loop).
            for (int c = 0; c < W; ++c)
            {
                const float rel = best[c] * inv_tol[c];
                score[c] = on[c] == id ? a * (1.f - 0.5f * rel * rel) : score[c];
            }
            for (int c = 0; c < W; ++c) own[c] = on[c] == id ? mark : own[c];
            for (int c = 0; c < W; ++c) sem[c] = on[c] == id ? cls : sem[c];
        }
    }
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
    if (K.width != depth.width || K.height != depth.height || depth.size() != size_t(depth.width) * depth.height)
        throw InputError(fmt::format("detector labeller: depth image is {}x{} but the intrinsics are for {}x{}",
                                     depth.width, depth.height, K.width, K.height));
    if (!K.valid()) throw InputError("detector labeller: invalid intrinsics");
    if (depth.width > 65535 || depth.height > 65535)  // the mask grower packs (x, y) in 32 bits
        throw InputError(fmt::format("detector labeller: {}x{} depth image is too large", depth.width, depth.height));
    if (!up_cam.allFinite() || up_cam.norm() < 1e-9) throw InputError("detector labeller: gravity 'up' is not a direction");
    const int W = depth.width, H = depth.height;
    GeometryLabelStats stats;
    // Sized without filling where they fit: the stuff pass writes every pixel of the first two.
    const size_t N = size_t(W) * H;
    const auto fit = [&](auto& image) {
        if (image.width != W || image.height != H || image.size() != N) image.resize(W, H);
    };
    fit(out.semantic);
    fit(out.semantic_score);
    fit(out.instance);
    fit(out.panoptic_score);
    std::fill(out.instance.data.begin(), out.instance.data.end(), 0u);
    std::fill(out.panoptic_score.data.begin(), out.panoptic_score.data.end(), 0.f);
    auto& owner = work_->owner;
    owner.resize(N);

    // Stuff: floor, ceiling, walls from the depth planes.
    const auto& planes = work_->planes.find(depth, K, up_cam);
    for (const auto& p : planes)
        (p.kind == PlaneKind::Floor ? stats.planes_floor : p.kind == PlaneKind::Ceiling ? stats.planes_ceiling
                                                                                       : stats.planes_wall)++;
    uint16_t kind_class[3];
    kind_class[int(PlaneKind::Floor)] = uint16_t(floor_);
    kind_class[int(PlaneKind::Ceiling)] = uint16_t(ceiling_);
    kind_class[int(PlaneKind::Wall)] = uint16_t(wall_);
    work_->labelStuff(depth, K, planes, kind_class, out);

    // Things: detections in score order, each the depth segment of its box; higher scores first
    // so that where masks would overlap the higher score owns the pixel.
    auto& order = work_->order;
    order.resize(detections.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    // Equal scores keep their input order (std::sort with the index as tie-break: stable_sort
    // would allocate a buffer every frame).
    // (NaN and non-positive scores sort as 0: a strict weak order; they are dropped below.)
    const auto key = [&](size_t k) { return detections[k].score > 0 ? detections[k].score : 0.f; };
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        const float sa = key(a), sb = key(b);
        return sa > sb || (sa == sb && a < b);
    });
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
        for (const int i : work_->masks.pixels())
        {
            out.semantic.data[size_t(i)] = cls;
            out.semantic_score.data[size_t(i)] = s;
            out.instance.data[size_t(i)] = id;
            out.panoptic_score.data[size_t(i)] = s * s;
        }
    }
    return stats;
}

}  // namespace pndt::seg
