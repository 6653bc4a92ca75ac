#include "depth_planes.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace pndt::seg
{
namespace
{
constexpr double kPi = 3.14159265358979323846;

/// Least-squares plane through points[idx] (smallest-eigenvalue normal of the covariance),
/// oriented to face the camera (d > 0).
bool fitPlane(const std::vector<Eigen::Vector3f>& points, const std::vector<uint32_t>& idx, StructuralPlane& p)
{
    if (idx.size() < 3) return false;
    // Sums relative to the first point (keeps the covariance exact far from the camera).
    const Eigen::Vector3d o = points[idx[0]].cast<double>();
    double sx = 0, sy = 0, sz = 0, xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
    for (uint32_t i : idx)
    {
        const double x = points[i].x() - o.x(), y = points[i].y() - o.y(), z = points[i].z() - o.z();
        sx += x, sy += y, sz += z;
        xx += x * x, xy += x * y, xz += x * z, yy += y * y, yz += y * z, zz += z * z;
    }
    const double m = double(idx.size());
    const Eigen::Vector3d s(sx, sy, sz);
    const Eigen::Vector3d mean = o + s / m;
    Eigen::Matrix3d cov;
    cov << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    cov -= s * s.transpose() / m;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    Eigen::Vector3d n = es.eigenvectors().col(0);
    double d = -n.dot(mean);
    if (d < 0) n = -n, d = -d;
    if (!std::isfinite(d) || !n.allFinite()) return false;
    p.n = n.cast<float>();
    p.d = float(d);
    return true;
}

bool validDepth(float z) { return z > 0 && std::isfinite(z); }
}  // namespace

void PlaneFinder::samplePoints(const Image<float>& depth, const CameraIntrinsics& K)
{
    points_.clear();
    cell_of_point_.clear();
    // One sample per grid cell, at the cell's centre pixel (clamped into the image).
    for (int gy = 0; gy < grid_h_; ++gy)
        for (int gx = 0; gx < grid_w_; ++gx)
        {
            const int r = std::min(depth.height - 1, gy * step_ + step_ / 2);
            const int c = std::min(depth.width - 1, gx * step_ + step_ / 2);
            const float z = depth.at(r, c);
            if (!validDepth(z)) continue;
            points_.push_back(K.unproject(c, r, z).cast<float>());
            cell_of_point_.push_back(gy * grid_w_ + gx);
        }
}

bool PlaneFinder::ransac(const Eigen::Vector3f& up, SplitMix64& rng, StructuralPlane& best)
{
    // Hypotheses are scored on at most 1000 random remaining points.
    const uint32_t R = uint32_t(remaining_.size());
    subset_.clear();
    const size_t m = std::min<size_t>(1000, R);
    for (size_t k = 0; k < m; ++k) subset_.push_back(remaining_[rng.below(R)]);

    size_t best_score = 0;
    // Adaptive stop: enough draws that an all-inlier triple of the best plane so far was drawn
    // with 99.9 % probability (deterministic: it only depends on the scores).
    uint32_t needed = o_.ransac_iterations;
    for (uint32_t it = 0; it < needed; ++it)
    {
        const Eigen::Vector3f& a = points_[remaining_[rng.below(R)]];
        const Eigen::Vector3f& b = points_[remaining_[rng.below(R)]];
        const Eigen::Vector3f& c = points_[remaining_[rng.below(R)]];
        Eigen::Vector3f n = (b - a).cross(c - a);
        const float len = n.norm();
        if (!(len > 1e-9f)) continue;
        n /= len;
        const float cu = std::abs(n.dot(up));
        if (cu < cos_h_ && cu > sin_v_) continue;  // neither horizontal nor vertical
        const float d = -n.dot(a);
        size_t score = 0;
        for (uint32_t i : subset_)
            score += std::abs(n.dot(points_[i]) + d) < tolerance(points_[i].z()) ? 1 : 0;
        if (score <= best_score) continue;
        best_score = score;
        best.n = n;
        best.d = d;
        const double w = double(score) / double(m);
        const double miss = 1.0 - w * w * w;
        if (miss <= 1e-12)
            needed = std::min(needed, it + 1);
        else
            needed = std::min<uint32_t>(needed, uint32_t(std::ceil(std::log(1e-3) / std::log(miss))) + 1);
    }
    return best_score >= 3;
}

void PlaneFinder::collectInliers(const StructuralPlane& p)
{
    inliers_.clear();
    for (uint32_t i : remaining_)
        if (std::abs(p.n.dot(points_[i]) + p.d) < tolerance(points_[i].z())) inliers_.push_back(i);
}

bool PlaneFinder::classify(StructuralPlane& p, const Eigen::Vector3f& up) const
{
    const float c = p.n.dot(up);
    if (std::abs(c) >= cos_h_)
    {
        // n faces the camera: n·up > 0 means the camera is above the plane.
        p.kind = c > 0 ? PlaneKind::Floor : PlaneKind::Ceiling;
        p.gravity_agreement = std::abs(c);
        return true;
    }
    if (std::abs(c) > sin_v_) return false;
    // A wall is large: its inliers span min_wall_extent horizontally and vertically.
    const Eigen::Vector3f along = up.cross(p.n).normalized();
    float h0 = 1e9f, h1 = -1e9f, v0 = 1e9f, v1 = -1e9f;
    for (uint32_t i : inliers_)
    {
        const float h = points_[i].dot(along), v = points_[i].dot(up);
        h0 = std::min(h0, h), h1 = std::max(h1, h);
        v0 = std::min(v0, v), v1 = std::max(v1, v);
    }
    const float extent = float(o_.min_wall_extent);
    if (h1 - h0 < extent || v1 - v0 < extent) return false;
    p.kind = PlaneKind::Wall;
    p.gravity_agreement = std::sqrt(std::max(0.f, 1.f - c * c));
    return true;
}

void PlaneFinder::keepLargestRegion()
{
    // Label the inliers' cells, flood-fill each 4-connected group, keep the largest.
    const size_t cells = size_t(grid_w_) * grid_h_;
    component_.assign(cells, -2);  // -2 = not an inlier, -1 = inlier not yet visited
    for (uint32_t i : inliers_) component_[size_t(cell_of_point_[i])] = -1;
    int best = -1, label = 0;
    size_t best_size = 0;
    for (uint32_t i0 : inliers_)
    {
        const size_t c0 = size_t(cell_of_point_[i0]);
        if (component_[c0] != -1) continue;
        size_t size = 0;
        stack_.assign(1, int32_t(c0));
        component_[c0] = label;
        while (!stack_.empty())
        {
            const int c = stack_.back();
            stack_.pop_back();
            ++size;
            const int x = c % grid_w_, y = c / grid_w_;
            const int nb[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
            for (const auto& q : nb)
            {
                if (q[0] < 0 || q[1] < 0 || q[0] >= grid_w_ || q[1] >= grid_h_) continue;
                const size_t n = size_t(q[1]) * grid_w_ + q[0];
                if (component_[n] != -1) continue;
                component_[n] = label;
                stack_.push_back(int32_t(n));
            }
        }
        if (size > best_size) best_size = size, best = label;
        ++label;
    }
    size_t kept = 0;
    for (uint32_t i : inliers_)
        if (component_[size_t(cell_of_point_[i])] == best) inliers_[kept++] = i;
    inliers_.resize(kept);
}

void PlaneFinder::selectAndMarkRegions()
{
    // Only the lowest horizontal plane below the camera is floor (a table top is not), only the
    // highest above it ceiling: the largest distance d from the camera.
    int lowest = -1, highest = -1;
    for (int k = 0; k < int(accepted_.size()); ++k)
    {
        const auto& p = accepted_[size_t(k)];
        if (p.kind == PlaneKind::Floor && (lowest < 0 || p.d > accepted_[size_t(lowest)].d)) lowest = k;
        if (p.kind == PlaneKind::Ceiling && (highest < 0 || p.d > accepted_[size_t(highest)].d)) highest = k;
    }
    uint32_t kept_bits = 0;
    for (int k = 0; k < int(accepted_.size()); ++k)
        if (accepted_[size_t(k)].kind == PlaneKind::Wall || k == lowest || k == highest)
        {
            kept_bits |= 1u << k;
            planes_.push_back(accepted_[size_t(k)]);
        }
    // near_ = the kept planes' regions dilated by one cell, bits renumbered to planes_' order.
    const size_t cells = size_t(grid_w_) * grid_h_;
    near_.assign(cells, 0);
    if (planes_.empty()) return;
    const bool renumber = kept_bits != (accepted_.size() >= 32 ? ~0u : (1u << accepted_.size()) - 1);
    for (int gy = 0; gy < grid_h_; ++gy)
        for (int gx = 0; gx < grid_w_; ++gx)
        {
            uint32_t bits = region_bits_[size_t(gy) * grid_w_ + gx] & kept_bits;
            if (!bits) continue;
            if (renumber)
            {
                uint32_t packed = 0;
                for (int k = 0, j = 0; k < int(accepted_.size()); ++k)
                    if (kept_bits >> k & 1u) packed |= (bits >> k & 1u) << j++;
                bits = packed;
            }
            for (int y = std::max(0, gy - 1); y <= std::min(grid_h_ - 1, gy + 1); ++y)
                for (int x = std::max(0, gx - 1); x <= std::min(grid_w_ - 1, gx + 1); ++x)
                    near_[size_t(y) * grid_w_ + x] |= bits;
        }
}

const std::vector<StructuralPlane>& PlaneFinder::find(const Image<float>& depth, const CameraIntrinsics& K,
                                                      const Eigen::Vector3d& up_cam)
{
    planes_.clear();
    accepted_.clear();
    step_ = std::max(1, o_.plane_sample_step);
    grid_w_ = (depth.width + step_ - 1) / step_;
    grid_h_ = (depth.height + step_ - 1) / step_;
    const size_t cells = size_t(grid_w_) * grid_h_;
    region_bits_.assign(cells, 0);
    cos_h_ = float(std::cos(o_.horizontal_tolerance_deg * kPi / 180));
    sin_v_ = float(std::sin(o_.vertical_tolerance_deg * kPi / 180));
    samplePoints(depth, K);
    const size_t total = points_.size();
    if (total < 3)
    {
        selectAndMarkRegions();
        return planes_;
    }
    const Eigen::Vector3f up = up_cam.cast<float>().normalized();
    const size_t min_samples = std::max<size_t>(3, size_t(o_.min_plane_share * double(total)));
    const int max_planes = std::min(o_.max_planes, kMaxPlanes);

    remaining_.resize(total);
    for (uint32_t i = 0; i < total; ++i) remaining_[i] = i;
    is_inlier_.assign(total, 0);
    claimed_.assign(total, 0);
    SplitMix64 rng(o_.seed);
    int rejected_in_a_row = 0;
    while (int(accepted_.size()) < max_planes && remaining_.size() >= min_samples && rejected_in_a_row < 3)
    {
        StructuralPlane p;
        if (!ransac(up, rng, p)) break;
        // All inliers of the winner, least-squares refit, inliers again with the refitted plane.
        collectInliers(p);
        if (fitPlane(points_, inliers_, p)) collectInliers(p);
        if (inliers_.size() < min_samples) break;
        // All inliers leave the pool whether or not the plane is structural (a table top found
        // once must not be found again).
        for (uint32_t i : inliers_) is_inlier_[i] = 1;
        remaining_.erase(std::remove_if(remaining_.begin(), remaining_.end(), [&](uint32_t i) { return is_inlier_[i]; }),
                         remaining_.end());
        // The plane's points: all within tolerance that no accepted plane has claimed, including
        // those an earlier rejected plane took from the pool (the floor in front of a table's
        // front side is on both).
        inliers_.clear();
        for (uint32_t i = 0; i < total; ++i)
            if (!claimed_[i] && std::abs(p.n.dot(points_[i]) + p.d) < tolerance(points_[i].z())) inliers_.push_back(i);
        // Vertical planes keep their largest connected region (a wall, not the coplanar side of a
        // cabinet elsewhere); a horizontal plane is floor or ceiling wherever it is seen.
        if (std::abs(p.n.dot(up)) < cos_h_)
        {
            keepLargestRegion();
            fitPlane(points_, inliers_, p);
        }
        p.samples = inliers_.size();
        if (p.samples >= min_samples && classify(p, up))
        {
            const uint32_t bit = 1u << accepted_.size();
            for (uint32_t i : inliers_)
            {
                region_bits_[size_t(cell_of_point_[i])] |= bit;
                claimed_[i] = 1;
            }
            accepted_.push_back(p);
            rejected_in_a_row = 0;
        }
        else
            ++rejected_in_a_row;
    }
    selectAndMarkRegions();
    return planes_;
}

}  // namespace pndt::seg
