// Floor, ceiling and wall planes of one depth image (internal to the detector front-end).
#pragma once

#include <pndt/seg/detector_geometry.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace pndt::seg
{
enum class PlaneKind : uint8_t
{
    Floor,
    Ceiling,
    Wall
};

/// n·p + d = 0 in the camera frame, n unit and facing the camera (d > 0).
struct StructuralPlane
{
    Eigen::Vector3f n = Eigen::Vector3f::Zero();
    float d = 0;
    PlaneKind kind = PlaneKind::Wall;
    float gravity_agreement = 0;  ///< |n·up| for floor / ceiling, sqrt(1 − (n·up)²) for walls
    size_t samples = 0;           ///< inlier samples (walls: of the largest connected region)
};

/// Small deterministic generator (splitmix64): the same planes for a seed on every standard
/// library (std::uniform_int_distribution is implementation-defined).
class SplitMix64
{
   public:
    explicit SplitMix64(uint64_t seed) : s_(seed) {}
    uint64_t next()
    {
        uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, n) (multiply-shift; the bias is < n / 2^32, irrelevant here).
    uint32_t below(uint32_t n) { return uint32_t(((next() >> 32) * uint64_t(n)) >> 32); }

   private:
    uint64_t s_;
};

/// Sequential RANSAC on a subsampled point cloud. Hypotheses whose normal is neither near
/// gravity nor near horizontal are rejected before scoring (only structural planes are sought);
/// each hypothesis is scored on a fixed random subset, the winner refitted by least squares to
/// all its inliers. Deterministic for a seed; buffers reused between frames (no allocation once
/// they have grown to the frame size).
///
/// Each plane has a region on the sample grid (cells of step × step pixels): only pixels in or
/// next to a region cell are labelled with it. A wall's region is its largest connected part, so
/// a cabinet front that happens to lie on the wall's plane elsewhere in the image does not become
/// wall; floor and ceiling keep all their cells.
class PlaneFinder
{
   public:
    /// Planes are tracked as bits of a cell mask.
    static constexpr int kMaxPlanes = 32;

    explicit PlaneFinder(const GeometryLabelOptions& o) : o_(o) {}
    const std::vector<StructuralPlane>& find(const Image<float>& depth, const CameraIntrinsics& K,
                                             const Eigen::Vector3d& up_cam);

    int gridWidth() const { return grid_w_; }
    int step() const { return step_; }
    /// Per sample-grid cell of image row `row`: bit k set when the cell is in or next to a region
    /// cell of plane k of the last find().
    const uint32_t* nearRow(int row) const { return near_.data() + size_t(row / step_) * size_t(grid_w_); }

    /// Inlier distance at depth z (grows with z, as depth noise does).
    float tolerance(float z) const { return float(o_.plane_inlier_distance) * std::max(1.f, z / 2.f); }

   private:
    void samplePoints(const Image<float>& depth, const CameraIntrinsics& K);
    /// Best structural hypothesis on remaining_; false when none has 3 inliers.
    bool ransac(const Eigen::Vector3f& up, SplitMix64& rng, StructuralPlane& p);
    /// inliers_ = the remaining points within tolerance of p.
    void collectInliers(const StructuralPlane& p);
    bool classify(StructuralPlane& p, const Eigen::Vector3f& up) const;
    /// Keeps the largest 4-connected (on the sample grid) part of inliers_.
    void keepLargestRegion();
    /// Keeps walls, the lowest floor and the highest ceiling; builds near_ from region_bits_.
    void selectAndMarkRegions();

    const GeometryLabelOptions& o_;
    int grid_w_ = 0, grid_h_ = 0, step_ = 1;
    float cos_h_ = 1, sin_v_ = 0;  ///< from the tolerances
    std::vector<Eigen::Vector3f> points_;
    std::vector<int32_t> cell_of_point_;
    std::vector<int32_t> component_, stack_;
    std::vector<uint32_t> remaining_, subset_, inliers_;
    std::vector<uint8_t> is_inlier_;     ///< per point: inlier of a plane found (left the pool)
    std::vector<uint8_t> claimed_;       ///< per point: in the region of an accepted plane
    std::vector<uint32_t> region_bits_;  ///< per cell: bit k = inlier of accepted plane k
    std::vector<uint32_t> near_;         ///< per cell: bit k = region of kept plane k, dilated by a cell
    std::vector<StructuralPlane> accepted_, planes_;
};

}  // namespace pndt::seg
