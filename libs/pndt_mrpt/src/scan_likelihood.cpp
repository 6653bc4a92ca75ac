// NDT scan likelihood and matching ratio (scan_likelihood.h).
#include <pndt/mrpt/observation_frame.h>
#include <pndt/mrpt/scan_likelihood.h>

#include <algorithm>

namespace pndt
{
double ndtLogLikelihood(const PanopticMap& map, const std::vector<Eigen::Vector3d>& world_points,
                        double outlier_mahalanobis_sq)
{
    const double floor_term = -0.5 * outlier_mahalanobis_sq;
    double loglik = 0;
    for (const Eigen::Vector3d& p : world_points)
    {
        const PointLabel l = map.labelAt(p);
        loglik += l.found ? std::max(floor_term, -0.5 * l.mahalanobis_sq) : floor_term;
    }
    return loglik;
}

double ndtMatchingRatio(const PanopticMap& map, const std::vector<Eigen::Vector3d>& world_points,
                        double max_mahalanobis_sq)
{
    if (world_points.empty()) return 0;
    size_t matched = 0;
    for (const Eigen::Vector3d& p : world_points)
    {
        const PointLabel l = map.labelAt(p);
        if (l.found && l.mahalanobis_sq <= max_mahalanobis_sq) ++matched;
    }
    return double(matched) / double(world_points.size());
}

std::vector<Eigen::Vector3d> scanPointsInWorld(const mrpt::obs::CObservation3DRangeScan& scan,
                                               const mrpt::poses::CPose3D& robot, int decimation, double max_range)
{
    PanopticFrame f;
    depthFrameFrom(scan, f);
    const Pose T = cameraPoseInWorld(robot, scan.sensorPose);
    const int step = std::max(1, decimation);
    std::vector<Eigen::Vector3d> pts;
    pts.reserve(size_t(f.K.width / step + 1) * size_t(f.K.height / step + 1));
    for (int r = step / 2; r < f.K.height; r += step)
        for (int c = step / 2; c < f.K.width; c += step)
        {
            const float z = f.depth.at(r, c);
            if (!(z > 0) || z > max_range) continue;
            pts.push_back(T * f.K.unproject(c, r, z));
        }
    return pts;
}

std::vector<Eigen::Vector3d> scanPointsInWorld(const mrpt::obs::CObservation2DRangeScan& scan,
                                               const mrpt::poses::CPose3D& robot, int decimation, double max_range)
{
    const mrpt::poses::CPose3D sensor = robot + scan.sensorPose;
    const size_t step = size_t(std::max(1, decimation));
    std::vector<Eigen::Vector3d> pts;
    for (size_t i = 0; i < scan.getScanSize(); i += step)
    {
        if (!scan.getScanRangeValidity(i)) continue;
        const double r = scan.getScanRange(i);
        if (!(r > 0) || r > max_range || r >= scan.maxRange) continue;
        const double a = scan.getScanAngle(i);
        double x, y, z;
        sensor.composePoint(r * std::cos(a), r * std::sin(a), 0.0, x, y, z);
        pts.emplace_back(x, y, z);
    }
    return pts;
}

}  // namespace pndt
