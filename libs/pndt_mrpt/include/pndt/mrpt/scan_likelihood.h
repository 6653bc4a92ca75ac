// How well a scan fits the map's Gaussians: what MRPT's particle-filter
// localisers (CMonteCarloLocalization2D/3D) and matchers ask a metric map for.
// Each scan point is scored under the nearest voxel Gaussian (labelAt: own voxel
// and its 26 neighbours) as -m²/2, truncated at -outlier/2 so a moved chair or an
// unmapped corner costs a bounded amount (a robust NDT score, Biber & Straßer).
#pragma once

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <pndt/panoptic_map.h>

#include <vector>

namespace pndt
{
struct LikelihoodOptions
{
    /// Depth images: every n-th pixel in rows and columns (8: ~1200 points at 320x240).
    int depth_decimation = 8;
    /// 2D scans: every n-th ray.
    int scan_decimation = 1;
    /// Squared Mahalanobis distance at which a point counts as an outlier.
    double outlier_mahalanobis_sq = 9.0;
    /// Points beyond this range (metres) are left out (0 = the map's max_range).
    double max_range = 0;

    bool operator==(const LikelihoodOptions& o) const
    {
        return depth_decimation == o.depth_decimation && scan_decimation == o.scan_decimation &&
               outlier_mahalanobis_sq == o.outlier_mahalanobis_sq && max_range == o.max_range;
    }
};

/// Sum over points of max(-m²/2, -outlier/2); points with no occupied voxel near
/// them count as outliers. 0 for no points.
double ndtLogLikelihood(const PanopticMap& map, const std::vector<Eigen::Vector3d>& world_points,
                        double outlier_mahalanobis_sq);

/// Share of points within `max_mahalanobis_sq` of a Gaussian (or inside an occupied
/// voxel without one); 0 for no points.
double ndtMatchingRatio(const PanopticMap& map, const std::vector<Eigen::Vector3d>& world_points,
                        double max_mahalanobis_sq);

/// The decimated points of a depth image, in world coordinates for robot pose `robot`.
std::vector<Eigen::Vector3d> scanPointsInWorld(const mrpt::obs::CObservation3DRangeScan& scan,
                                               const mrpt::poses::CPose3D& robot, int decimation, double max_range);
/// The valid rays of a 2D scan (every `decimation`-th), in world coordinates.
std::vector<Eigen::Vector3d> scanPointsInWorld(const mrpt::obs::CObservation2DRangeScan& scan,
                                               const mrpt::poses::CPose3D& robot, int decimation, double max_range);

}  // namespace pndt
