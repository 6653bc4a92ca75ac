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
    Eigen::Vector3f n;
    float d = 0;
    PlaneKind kind = PlaneKind::Wall;
    float gravity_agreement = 0;  ///< |n·up| for floor / ceiling, sqrt(1 − (n·up)²) for walls
    size_t samples = 0;           ///< inlier samples (walls: of the largest connected region)
    /// The plane's region on the sample grid (grid_w × grid_h cells of sample_step pixels): only
    /// pixels in or next to a region cell are labelled with the plane. A wall's region is its
    /// largest connected part, so a cabinet front that happens to lie on the wall's plane
    /// elsewhere in the image does not become wall; floor and ceiling keep all their cells.
    std::vector<uint8_t> region;
};

/// Sequential RANSAC on a subsampled point cloud. Hypotheses whose normal is neither near
/// gravity nor near horizontal are rejected before scoring (only structural planes are sought);
/// each hypothesis is scored on a fixed random subset, the winner refitted by least squares to
/// all its inliers. Deterministic for a seed; buffers reused between frames.
class PlaneFinder
{
   public:
    explicit PlaneFinder(const GeometryLabelOptions& o) : o_(o) {}
    const std::vector<StructuralPlane>& find(const Image<float>& depth, const CameraIntrinsics& K,
                                             const Eigen::Vector3d& up_cam);

    int gridWidth() const { return grid_w_; }
    int gridHeight() const { return grid_h_; }
    int step() const { return step_; }
    /// Whether pixel (row, col) is in or next to a region cell of plane p.
    bool nearRegion(const StructuralPlane& p, int row, int col) const;

    /// Inlier distance at depth z (grows with z, as depth noise does).
    float tolerance(float z) const { return float(o_.plane_inlier_distance) * std::max(1.f, z / 2.f); }

   private:
    bool classify(StructuralPlane& p, const Eigen::Vector3f& up, const std::vector<uint32_t>& inliers) const;
    /// Keeps the largest 4-connected (on the sample grid) part of inliers_; fills p.region.
    void keepLargestRegion(StructuralPlane& p);

    const GeometryLabelOptions& o_;
    int grid_w_ = 0, grid_h_ = 0, step_ = 1;
    std::vector<Eigen::Vector3f> points_;
    std::vector<int32_t> cell_of_point_, point_of_cell_;  ///< sample grid ↔ point index (−1 = none)
    std::vector<int32_t> component_, stack_;
    std::vector<uint32_t> remaining_, subset_, inliers_;
    std::vector<StructuralPlane> planes_;
};

}  // namespace pndt::seg
