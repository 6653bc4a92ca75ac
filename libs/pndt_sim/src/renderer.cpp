// render(): per-pixel exact ray casting with conservative screen-space culling.
//
// Each primitive's bounding corners are projected to get a pixel rectangle
// (widened by one pixel against rounding); pixels outside it cannot see the
// primitive, so skipping them keeps the result exact. Primitives that are
// partly behind the camera get the whole image.
#include "pndt/sim/renderer.h"

#include <cmath>
#include <vector>

#include "pndt/sim/raycast.h"
#include "primitive_geometry.h"

namespace pndt::sim
{
namespace
{
struct PixelRect
{
    int c0, c1, r0, r1;  // inclusive
};

/// False if the primitive cannot appear in the image (behind the camera or beyond
/// max_range); otherwise a conservative rectangle of the pixels that may see it.
bool screenRect(const detail::PreparedPrimitive& p, const Pose& T_cam_world,
                const CameraIntrinsics& K, double max_range, PixelRect& rect)
{
    constexpr double kNearZ = 1e-6;
    double min_z = detail::kInf, max_z = -detail::kInf;
    double min_c = detail::kInf, max_c = -detail::kInf;
    double min_r = detail::kInf, max_r = -detail::kInf;
    for (int i = 0; i < 8; ++i)
    {
        const Eigen::Vector3d local((i & 1) ? p.half.x() : -p.half.x(),
                                    (i & 2) ? p.half.y() : -p.half.y(),
                                    (i & 4) ? p.half.z() : -p.half.z());
        const Eigen::Vector3d c = T_cam_world * (p.center + p.toWorld(local));
        min_z = std::min(min_z, c.z());
        max_z = std::max(max_z, c.z());
        if (c.z() > kNearZ)
        {
            const double col = K.fx * c.x() / c.z() + K.cx;
            const double row = K.fy * c.y() / c.z() + K.cy;
            min_c = std::min(min_c, col);
            max_c = std::max(max_c, col);
            min_r = std::min(min_r, row);
            max_r = std::max(max_r, row);
        }
    }
    if (max_z < -kNearZ) return false;                     // entirely behind the camera
    if (min_z > max_range * (1 + 1e-9) + kNearZ) return false;  // entirely beyond range
    if (min_z <= kNearZ)
    {
        rect = {0, K.width - 1, 0, K.height - 1};  // straddles the camera plane
        return true;
    }
    // Clamp in double first: projections of near corners can be huge.
    auto clampIdx = [](double v, int hi) {
        return static_cast<int>(std::max(0.0, std::min(v, static_cast<double>(hi))));
    };
    rect.c0 = clampIdx(std::floor(min_c) - 1, K.width - 1);
    rect.c1 = clampIdx(std::ceil(max_c) + 1, K.width - 1);
    rect.r0 = clampIdx(std::floor(min_r) - 1, K.height - 1);
    rect.r1 = clampIdx(std::ceil(max_r) + 1, K.height - 1);
    if (max_c < -1 || min_c > K.width || max_r < -1 || min_r > K.height) return false;
    return true;
}

template <typename T>
void ensureSize(Image<T>& img, int w, int h)
{
    if (!img.sameSize(w, h) || img.size() != static_cast<size_t>(w) * h) img.resize(w, h);
}

}  // namespace

void render(const Scene& scene, const Pose& T_world_cam, const CameraIntrinsics& K,
            RenderedFrame& out, double max_range)
{
    if (!K.valid()) throw InputError("pndt::sim::render: invalid camera intrinsics");
    const int W = K.width, H = K.height;
    ensureSize(out.depth, W, H);
    ensureSize(out.semantic, W, H);
    ensureSize(out.instance, W, H);

    const Pose T_cam_world = T_world_cam.inverse(Eigen::Isometry);
    const Eigen::Matrix3d R = T_world_cam.linear();
    const Eigen::Vector3d eye = T_world_cam.translation();

    // Visible primitives in scene order (order decides ties, as in castRay).
    std::vector<detail::PreparedPrimitive> prims;
    std::vector<PixelRect> rects;
    prims.reserve(scene.primitives.size());
    rects.reserve(scene.primitives.size());
    for (const Primitive& prim : scene.primitives)
    {
        detail::PreparedPrimitive p(prim);
        PixelRect r;
        if (!screenRect(p, T_cam_world, K, max_range, r)) continue;
        prims.push_back(p);
        rects.push_back(r);
    }
    const bool has_room = !scene.room.isEmpty();

    std::vector<double> xn(static_cast<size_t>(W));
    for (int col = 0; col < W; ++col) xn[col] = (col - K.cx) / K.fx;

    std::vector<int> active;
    active.reserve(prims.size());
    for (int row = 0; row < H; ++row)
    {
        active.clear();
        for (int k = 0; k < static_cast<int>(prims.size()); ++k)
            if (rects[k].r0 <= row && row <= rects[k].r1) active.push_back(k);
        const double yn = (row - K.cy) / K.fy;
        const size_t base = static_cast<size_t>(row) * W;

        for (int col = 0; col < W; ++col)
        {
            const Eigen::Vector3d d = pixelRayDirection(R, xn[col], yn);
            double best = detail::kInf;
            uint16_t sem = 0;
            uint32_t inst = 0;
            for (int k : active)
            {
                if (col < rects[k].c0 || col > rects[k].c1) continue;
                double t;
                if (detail::intersect(prims[k], eye, d, t) && t < best)
                {
                    best = t;
                    sem = prims[k].semantic;
                    inst = prims[k].instance;
                }
            }
            double t;
            uint16_t room_sem;
            if (has_room && detail::intersectRoom(scene.room, eye, d, t, room_sem) && t < best)
            {
                best = t;
                sem = room_sem;
                inst = 0;
            }
            if (best > max_range)  // also the no-hit case (infinity)
            {
                out.depth.data[base + col] = 0.0f;
                out.semantic.data[base + col] = 0;
                out.instance.data[base + col] = 0;
            }
            else
            {
                out.depth.data[base + col] = static_cast<float>(best);
                out.semantic.data[base + col] = sem;
                out.instance.data[base + col] = inst;
            }
        }
    }
}

PanopticFrame renderPanopticFrame(const Scene& scene, const Pose& T_world_cam, const CameraIntrinsics& K, float score)
{
    RenderedFrame r;
    render(scene, T_world_cam, K, r);
    PanopticFrame f;
    f.K = K;
    f.depth = std::move(r.depth);
    f.semantic = std::move(r.semantic);
    f.semantic_score.resize(K.width, K.height, score);
    f.instance = std::move(r.instance);
    f.panoptic_score.resize(K.width, K.height, score);
    return f;
}

}  // namespace pndt::sim
