#include "depth_planes.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <random>

namespace pndt::seg
{
namespace
{
constexpr float kPi = 3.14159265358979f;

/// Least-squares plane through points[idx] (smallest-eigenvalue normal of the covariance).
bool fitPlane(const std::vector<Eigen::Vector3f>& points, const std::vector<uint32_t>& idx, Eigen::Vector3f& n,
              float& d)
{
    if (idx.size() < 3) return false;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (uint32_t i : idx) mean += points[i].cast<double>();
    mean /= double(idx.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (uint32_t i : idx)
    {
        const Eigen::Vector3d q = points[i].cast<double>() - mean;
        cov += q * q.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    Eigen::Vector3d nd = es.eigenvectors().col(0);
    double dd = -nd.dot(mean);
    if (dd < 0)
    {
        nd = -nd;
        dd = -dd;
    }
    n = nd.cast<float>();
    d = float(dd);
    return std::isfinite(d);
}
}  // namespace

bool PlaneFinder::classify(StructuralPlane& p, const Eigen::Vector3f& up, const std::vector<uint32_t>& inliers) const
{
    const float c = p.n.dot(up);
    const float cos_h = std::cos(float(o_.horizontal_tolerance_deg) * kPi / 180.f);
    const float sin_v = std::sin(float(o_.vertical_tolerance_deg) * kPi / 180.f);
    if (std::abs(c) >= cos_h)
    {
        // n faces the camera: n·up > 0 means the camera is above the plane.
        p.kind = c > 0 ? PlaneKind::Floor : PlaneKind::Ceiling;
        p.gravity_agreement = std::abs(c);
        return true;
    }
    if (std::abs(c) > sin_v) return false;
    // A wall is large: its inliers span min_wall_extent horizontally and vertically.
    const Eigen::Vector3f along = up.cross(p.n).normalized();
    float h0 = 1e9f, h1 = -1e9f, v0 = 1e9f, v1 = -1e9f;
    for (uint32_t i : inliers)
    {
        const float h = points_[i].dot(along), v = points_[i].dot(up);
        h0 = std::min(h0, h);
        h1 = std::max(h1, h);
        v0 = std::min(v0, v);
        v1 = std::max(v1, v);
    }
    const float extent = float(o_.min_wall_extent);
    if (h1 - h0 < extent || v1 - v0 < extent) return false;
    p.kind = PlaneKind::Wall;
    p.gravity_agreement = std::sqrt(std::max(0.f, 1.f - c * c));
    return true;
}

bool PlaneFinder::nearRegion(const StructuralPlane& p, int row, int col) const
{
    const int gy = row / step_, gx = col / step_;
    for (int y = std::max(0, gy - 1); y <= std::min(grid_h_ - 1, gy + 1); ++y)
        for (int x = std::max(0, gx - 1); x <= std::min(grid_w_ - 1, gx + 1); ++x)
            if (p.region[size_t(y) * grid_w_ + x]) return true;
    return false;
}

void PlaneFinder::keepLargestRegion(StructuralPlane& p)
{
    // Label the inliers' cells, flood-fill each 4-connected group, keep the largest.
    const size_t cells = size_t(grid_w_) * grid_h_;
    component_.assign(cells, -2);  // -2 = not an inlier, -1 = inlier not yet visited
    for (uint32_t i : inliers_) component_[size_t(cell_of_point_[i])] = -1;
    int best = -1;
    size_t best_size = 0;
    int label = 0;
    for (size_t c0 = 0; c0 < cells; ++c0)
    {
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
        if (size > best_size)
        {
            best_size = size;
            best = label;
        }
        ++label;
    }
    p.region.assign(cells, 0);
    size_t kept = 0;
    for (uint32_t i : inliers_)
        if (component_[size_t(cell_of_point_[i])] == best)
        {
            inliers_[kept++] = i;
            p.region[size_t(cell_of_point_[i])] = 1;
        }
    inliers_.resize(kept);
}

const std::vector<StructuralPlane>& PlaneFinder::find(const Image<float>& depth, const CameraIntrinsics& K,
                                                      const Eigen::Vector3d& up_cam)
{
    planes_.clear();
    points_.clear();
    cell_of_point_.clear();
    const int step = std::max(1, o_.plane_sample_step);
    step_ = step;
    grid_w_ = (depth.width + step - 1) / step;
    grid_h_ = (depth.height + step - 1) / step;
    // One sample per grid cell, at the cell's centre pixel (clamped into the image).
    for (int gy = 0; gy < grid_h_; ++gy)
        for (int gx = 0; gx < grid_w_; ++gx)
        {
            const int r = std::min(depth.height - 1, gy * step + step / 2);
            const int c = std::min(depth.width - 1, gx * step + step / 2);
            const float z = depth.at(r, c);
            if (!(z > 0) || !std::isfinite(z)) continue;
            points_.push_back(K.unproject(c, r, z).cast<float>());
            cell_of_point_.push_back(gy * grid_w_ + gx);
        }
    const size_t total = points_.size();
    if (total < 3) return planes_;
    const Eigen::Vector3f up = up_cam.cast<float>().normalized();
    const float cos_h = std::cos(float(o_.horizontal_tolerance_deg) * kPi / 180.f);
    const float sin_v = std::sin(float(o_.vertical_tolerance_deg) * kPi / 180.f);
    const size_t min_samples = std::max<size_t>(3, size_t(o_.min_plane_share * double(total)));

    remaining_.resize(total);
    for (uint32_t i = 0; i < total; ++i) remaining_[i] = i;
    std::mt19937_64 rng(o_.seed);
    int rejected_in_a_row = 0;
    while (int(planes_.size()) < o_.max_planes && remaining_.size() >= min_samples && rejected_in_a_row < 3)
    {
        // Score hypotheses on at most 1000 random remaining points.
        subset_.clear();
        const size_t m = std::min<size_t>(1000, remaining_.size());
        std::uniform_int_distribution<size_t> pick(0, remaining_.size() - 1);
        for (size_t k = 0; k < m; ++k) subset_.push_back(remaining_[pick(rng)]);

        Eigen::Vector3f best_n = Eigen::Vector3f::Zero();
        float best_d = 0;
        size_t best_score = 0;
        for (uint32_t it = 0; it < o_.ransac_iterations; ++it)
        {
            const Eigen::Vector3f& a = points_[remaining_[pick(rng)]];
            const Eigen::Vector3f& b = points_[remaining_[pick(rng)]];
            const Eigen::Vector3f& c = points_[remaining_[pick(rng)]];
            Eigen::Vector3f n = (b - a).cross(c - a);
            const float len = n.norm();
            if (len < 1e-9f) continue;
            n /= len;
            const float cu = std::abs(n.dot(up));
            if (cu < cos_h && cu > sin_v) continue;  // neither horizontal nor vertical
            const float d = -n.dot(a);
            size_t score = 0;
            for (uint32_t i : subset_)
                if (std::abs(n.dot(points_[i]) + d) < tolerance(points_[i].z())) ++score;
            if (score > best_score)
            {
                best_score = score;
                best_n = n;
                best_d = d;
            }
        }
        if (best_score < 3) break;

        // All inliers of the winner, refit, inliers again with the refitted plane.
        StructuralPlane p;
        p.n = best_n;
        p.d = best_d;
        for (int pass = 0; pass < 2; ++pass)
        {
            inliers_.clear();
            for (uint32_t i : remaining_)
                if (std::abs(p.n.dot(points_[i]) + p.d) < tolerance(points_[i].z())) inliers_.push_back(i);
            if (pass == 0 && !fitPlane(points_, inliers_, p.n, p.d)) break;
        }
        if (inliers_.size() < min_samples) break;
        // All inliers leave the pool whether or not the plane is structural (a table top found
        // once must not be found again); the plane itself is its largest connected region.
        std::vector<uint8_t> is_inlier(total, 0);
        for (uint32_t i : inliers_) is_inlier[i] = 1;
        // Vertical planes keep their largest connected region (a wall, not the coplanar side of a
        // cabinet elsewhere); a horizontal plane is floor or ceiling wherever it is seen.
        const float cu = std::abs(p.n.dot(up));
        if (cu < cos_h)
        {
            keepLargestRegion(p);
            if (inliers_.size() >= 3) fitPlane(points_, inliers_, p.n, p.d);
        }
        else
        {
            p.region.assign(size_t(grid_w_) * grid_h_, 0);
            for (uint32_t i : inliers_) p.region[size_t(cell_of_point_[i])] = 1;
        }
        p.samples = inliers_.size();
        remaining_.erase(std::remove_if(remaining_.begin(), remaining_.end(), [&](uint32_t i) { return is_inlier[i]; }),
                         remaining_.end());
        if (p.samples >= min_samples && classify(p, up, inliers_))
        {
            planes_.push_back(p);
            rejected_in_a_row = 0;
        }
        else
            ++rejected_in_a_row;
    }
    // Only the lowest horizontal plane below the camera is floor (a table top is not), only the
    // highest above it ceiling.
    const StructuralPlane* lowest = nullptr;
    const StructuralPlane* highest = nullptr;
    for (const auto& p : planes_)
    {
        if (p.kind == PlaneKind::Floor && (!lowest || p.d > lowest->d)) lowest = &p;
        if (p.kind == PlaneKind::Ceiling && (!highest || p.d > highest->d)) highest = &p;
    }
    std::vector<StructuralPlane> kept;
    for (const auto& p : planes_)
        if (p.kind == PlaneKind::Wall || &p == lowest || &p == highest) kept.push_back(p);
    planes_.swap(kept);
    return planes_;
}

}  // namespace pndt::seg
