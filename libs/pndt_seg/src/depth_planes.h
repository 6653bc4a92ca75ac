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
    size_t samples = 0;           ///< inlier samples
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

    /// Inlier distance at depth z (grows with z, as depth noise does).
    float tolerance(float z) const { return float(o_.plane_inlier_distance) * std::max(1.f, z / 2.f); }

   private:
    bool classify(StructuralPlane& p, const Eigen::Vector3f& up, const std::vector<uint32_t>& inliers) const;

    const GeometryLabelOptions& o_;
    std::vector<Eigen::Vector3f> points_;
    std::vector<uint32_t> remaining_, subset_, inliers_;
    std::vector<StructuralPlane> planes_;
};

}  // namespace pndt::seg
