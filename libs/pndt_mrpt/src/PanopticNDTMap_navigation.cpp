// PanopticNDTMap for MRPT's navigators and localisers: obstacle points
// (getAsSimplePointsMap), the NDT scan likelihood for 3D and 2D scans, the
// matching ratio and the distance to the closest obstacle.
#include <fmt/format.h>
#include <mrpt/maps/CPointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <pndt/mrpt/PanopticNDTMap.h>

#include <cmath>
#include <limits>
#include <stdexcept>

using mrpt::obs::CObservation2DRangeScan;
using mrpt::obs::CObservation3DRangeScan;

namespace pndt
{
namespace
{
double maxRangeFor(const LikelihoodOptions& o, const PanopticMap& map)
{
    return o.max_range > 0 ? o.max_range : map.options().max_range;
}
}  // namespace

bool PanopticNDTMap::internal_canComputeObservationLikelihood(const mrpt::obs::CObservation& obs) const
{
    // As computeObservationLikelihood reads them: a 3D scan needs its range image.
    if (IS_CLASS(obs, CObservation3DRangeScan)) return static_cast<const CObservation3DRangeScan&>(obs).hasRangeImage;
    return IS_CLASS(obs, CObservation2DRangeScan);
}

double PanopticNDTMap::internal_computeObservationLikelihood(const mrpt::obs::CObservation& obs,
                                                             const mrpt::poses::CPose3D& takenFrom) const
{
    const LikelihoodOptions& o = navigationOptions.likelihood;
    std::vector<Eigen::Vector3d> pts;
    if (IS_CLASS(obs, CObservation3DRangeScan))
        pts = scanPointsInWorld(static_cast<const CObservation3DRangeScan&>(obs), takenFrom, o.depth_decimation,
                                maxRangeFor(o, map_));
    else if (IS_CLASS(obs, CObservation2DRangeScan))
        pts = scanPointsInWorld(static_cast<const CObservation2DRangeScan&>(obs), takenFrom, o.scan_decimation,
                                maxRangeFor(o, map_));
    else
        return 0;
    return ndtLogLikelihood(map_, pts, o.outlier_mahalanobis_sq);
}

void PanopticNDTMap::OnPostSuccesfulInsertObs(const mrpt::obs::CObservation&) { obstacle_cache_.invalidate(); }

const mrpt::maps::CSimplePointsMap* PanopticNDTMap::getAsSimplePointsMap() const
{
    return &obstacle_cache_.get(map_, navigationOptions.obstacles);
}

float PanopticNDTMap::compute3DMatchingRatio(const mrpt::maps::CMetricMap* otherMap,
                                             const mrpt::poses::CPose3D& otherMapPose,
                                             const mrpt::maps::TMatchingRatioParams& params) const
{
    // Points of the other map: a points map itself, or what it exports as one.
    const auto* points = dynamic_cast<const mrpt::maps::CPointsMap*>(otherMap);
    if (!points && otherMap) points = otherMap->getAsSimplePointsMap();
    if (!points || points->empty()) return 0;
    std::vector<Eigen::Vector3d> pts;
    pts.reserve(points->size());
    for (size_t i = 0; i < points->size(); ++i)
    {
        float x, y, z;
        points->getPoint(i, x, y, z);
        double gx, gy, gz;
        otherMapPose.composePoint(x, y, z, gx, gy, gz);
        pts.emplace_back(gx, gy, gz);
    }
    const double maha = params.maxMahaDistForCorr;
    return float(ndtMatchingRatio(map_, pts, maha * maha));
}

float PanopticNDTMap::squareDistanceToClosestCorrespondence(float x0, float y0) const
{
    // MRPT's points map crashes on a NaN query point (its kd-tree).
    if (!std::isfinite(x0) || !std::isfinite(y0))
        throw std::invalid_argument(
            fmt::format("PanopticNDTMap::squareDistanceToClosestCorrespondence: the point ({}, {}) is not finite", x0, y0));
    const mrpt::maps::CSimplePointsMap* obstacles = getAsSimplePointsMap();
    if (obstacles->empty()) return 1e10f;
    return obstacles->squareDistanceToClosestCorrespondence(x0, y0);
}

}  // namespace pndt
