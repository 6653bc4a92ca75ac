// The plugin as MRPT's localisers see it: computeObservationLikelihood for a depth
// camera and a 2D laser peaks at the true pose, compute3DMatchingRatio and
// squareDistanceToClosestCorrespondence. On the map as built and as loaded.
#include <gtest/gtest.h>

#include <limits>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <pndt/mrpt/observation_frame.h>
#include <pndt/sim/raycast.h>
#include <pndt/sim/renderer.h>

#include <cmath>

#include "nav_test_scene.h"

using namespace pndt;
using mrpt::poses::CPose3D;

namespace
{
// The robot stands right of the middle, looking at table A; its camera sits 1.2 m
// up, pitched 20° down; its laser 0.3 m up, level, 180° wide.
const CPose3D kTruePose(0.3, -1.5, 0, std::atan2(1.5, -2.1), 0, 0);
const CPose3D kCameraOnRobot(0, 0, 1.2, 0, 20 * M_PI / 180, 0);
const CPose3D kLaserOnRobot(0, 0, 0.3, 0, 0, 0);

mrpt::obs::CObservation3DRangeScan depthScanAt(const CPose3D& robot)
{
    const CameraIntrinsics K = navtest::camera();
    sim::RenderedFrame r;
    sim::render(navtest::scene(), cameraPoseInWorld(robot, kCameraOnRobot), K, r);
    mrpt::obs::CObservation3DRangeScan o;
    o.sensorLabel = "RGBD";
    o.sensorPose = kCameraOnRobot;
    o.hasRangeImage = true;
    o.rangeImage_setSize(K.height, K.width);
    o.rangeUnits = 0.001f;
    o.range_is_depth = true;
    for (int row = 0; row < K.height; ++row)
        for (int col = 0; col < K.width; ++col) o.rangeImage(row, col) = uint16_t(std::lround(r.depth.at(row, col) * 1000));
    o.cameraParams.ncols = K.width;
    o.cameraParams.nrows = K.height;
    o.cameraParams.fx(K.fx);
    o.cameraParams.fy(K.fy);
    o.cameraParams.cx(K.cx);
    o.cameraParams.cy(K.cy);
    o.maxRange = 10;
    return o;
}

mrpt::obs::CObservation2DRangeScan laserScanAt(const CPose3D& robot)
{
    mrpt::obs::CObservation2DRangeScan s;
    s.sensorLabel = "LASER";
    s.sensorPose = kLaserOnRobot;
    s.aperture = float(M_PI);
    s.rightToLeft = true;
    s.maxRange = 20;
    s.resizeScan(181);
    const CPose3D sensor = robot + kLaserOnRobot;
    for (size_t i = 0; i < 181; ++i)
    {
        const double a = s.getScanAngle(i);
        double x, y, z;
        sensor.composePoint(std::cos(a), std::sin(a), 0.0, x, y, z);
        const Eigen::Vector3d o(sensor.x(), sensor.y(), sensor.z());
        const sim::RayHit h = sim::castRay(navtest::scene(), o, Eigen::Vector3d(x, y, z) - o, 20.0);
        s.setScanRange(i, h.hit ? float(h.t) : 0.f);
        s.setScanRangeValidity(i, h.hit);
    }
    return s;
}

std::vector<std::pair<std::string, CPose3D>> shiftedPoses()
{
    auto moved = [](double dx, double dy, double dyaw) {
        return CPose3D(kTruePose.x() + dx, kTruePose.y() + dy, 0, kTruePose.yaw() + dyaw, 0, 0);
    };
    const double deg = M_PI / 180;
    return {{"x+0.2 m", moved(0.2, 0, 0)},   {"x+1 m", moved(1, 0, 0)},       {"y-1 m", moved(0, -1, 0)},
            {"yaw+5 deg", moved(0, 0, 5 * deg)}, {"yaw+20 deg", moved(0, 0, 20 * deg)}, {"yaw-20 deg", moved(0, 0, -20 * deg)},
            {"1 m and 20 deg", moved(0.7, 0.7, 20 * deg)}};
}

class Localisation : public ::testing::TestWithParam<std::string>
{
   protected:
    const PanopticNDTMap& map() const { return navtest::mapNamed(GetParam()); }
};
}  // namespace

TEST_P(Localisation, DepthLikelihoodPeaksAtTheTruePose)
{
    const auto obs = depthScanAt(kTruePose);
    const mrpt::maps::CMetricMap& m = map();
    ASSERT_TRUE(m.canComputeObservationLikelihood(obs));
    const double at_true = m.computeObservationLikelihood(obs, kTruePose);
    const size_t n = scanPointsInWorld(obs, kTruePose, 8, 10).size();
    ASSERT_GT(n, 300u);
    // Nearly every point sits on a Gaussian: close to 0 per point.
    EXPECT_GT(at_true / double(n), -1.0) << at_true << " over " << n << " points";
    for (const auto& [name, pose] : shiftedPoses())
    {
        const double l = m.computeObservationLikelihood(obs, pose);
        std::cout << "  depth log-likelihood: true " << at_true << ", " << name << " " << l << "\n";
        EXPECT_GT(at_true, l) << name;
    }
}

// canCompute... said yes to a 3D scan without a range image, then compute... threw for it.
TEST_P(Localisation, AScanWithoutRangeImageIsOneItCannotScore)
{
    auto obs = depthScanAt(kTruePose);
    const mrpt::maps::CMetricMap& m = map();
    ASSERT_TRUE(m.canComputeObservationLikelihood(obs));
    obs.hasRangeImage = false;
    EXPECT_FALSE(m.canComputeObservationLikelihood(obs));
}

TEST_P(Localisation, LaserLikelihoodPeaksAtTheTruePose)
{
    const auto obs = laserScanAt(kTruePose);
    const mrpt::maps::CMetricMap& m = map();
    ASSERT_TRUE(m.canComputeObservationLikelihood(obs));
    const double at_true = m.computeObservationLikelihood(obs, kTruePose);
    for (const auto& [name, pose] : shiftedPoses())
    {
        const double l = m.computeObservationLikelihood(obs, pose);
        std::cout << "  laser log-likelihood: true " << at_true << ", " << name << " " << l << "\n";
        EXPECT_GT(at_true, l) << name;
    }
}

TEST_P(Localisation, GridSearchOverPosesFindsTheTruePose)
{
    // What a localiser does with the likelihood: the best of 21 x 21 x 9 poses
    // (±0.5 m in 5 cm steps, ±20° in 5° steps) around the truth is the truth.
    const auto obs = laserScanAt(kTruePose);
    const mrpt::maps::CMetricMap& m = map();
    double best = -1e300;
    CPose3D best_pose;
    for (int ix = -10; ix <= 10; ++ix)
        for (int iy = -10; iy <= 10; ++iy)
            for (int ia = -4; ia <= 4; ++ia)
            {
                const CPose3D p(kTruePose.x() + 0.05 * ix, kTruePose.y() + 0.05 * iy, 0,
                                kTruePose.yaw() + ia * 5 * M_PI / 180, 0, 0);
                const double l = m.computeObservationLikelihood(obs, p);
                if (l > best)
                {
                    best = l;
                    best_pose = p;
                }
            }
    EXPECT_NEAR(best_pose.x(), kTruePose.x(), 0.051);
    EXPECT_NEAR(best_pose.y(), kTruePose.y(), 0.051);
    EXPECT_NEAR(std::remainder(best_pose.yaw() - kTruePose.yaw(), 2 * M_PI), 0, 5.1 * M_PI / 180);
}

TEST_P(Localisation, MatchingRatioOfTheScanAsAPointsMap)
{
    // The scan's points in the robot frame; the map's pose relative to ours is the robot pose.
    mrpt::maps::CSimplePointsMap scan_points;
    for (const Eigen::Vector3d& p : scanPointsInWorld(depthScanAt(kTruePose), CPose3D(), 8, 10))
        scan_points.insertPoint(float(p.x()), float(p.y()), float(p.z()));
    mrpt::maps::TMatchingRatioParams params;
    params.maxMahaDistForCorr = 3;
    const float at_true = map().compute3DMatchingRatio(&scan_points, kTruePose, params);
    const float off = map().compute3DMatchingRatio(&scan_points, CPose3D(1.3, -0.8, 0, kTruePose.yaw() + 0.35, 0, 0), params);
    std::cout << "  matching ratio: true " << at_true << ", 1 m / 20 deg off " << off << "\n";
    EXPECT_GT(at_true, 0.9f);
    // About half of the points are floor, which matches under any shift along it.
    EXPECT_LT(off, 0.6f);
    EXPECT_GT(at_true - off, 0.35f);
}

TEST_P(Localisation, SquareDistanceToTheClosestObstacle)
{
    // (0, 2.5): the wall at y = 3 is the nearest obstacle, 0.5 m away.
    const float d2 = map().squareDistanceToClosestCorrespondence(0.f, 2.5f);
    EXPECT_NEAR(std::sqrt(d2), 0.5, 0.06);
}

TEST_P(Localisation, APoseThatIsNotFiniteScoresAsTheWorstNotTheBest)
{
    // A particle filter with one NaN particle must not lock onto it: every point of
    // a NaN pose is an outlier (the floor term), as far below the truth as a pose
    // off the map. Before, NaN keys landed on a voxel and scored 0, the maximum.
    const mrpt::maps::CMetricMap& m = map();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const auto& obs : {depthScanAt(kTruePose)})
    {
        const double at_true = m.computeObservationLikelihood(obs, kTruePose);
        const double off_map = m.computeObservationLikelihood(obs, CPose3D(500, 500, 0, 0, 0, 0));
        for (const CPose3D& bad : {CPose3D(nan, kTruePose.y(), 0, kTruePose.yaw(), 0, 0), CPose3D(nan, nan, nan, nan, nan, nan),
                                   CPose3D(1e30, 0, 0, 0, 0, 0)})
        {
            const double l = m.computeObservationLikelihood(obs, bad);
            EXPECT_EQ(l, off_map) << bad.asString();
            EXPECT_LT(l, at_true) << bad.asString();
        }
    }
    const auto laser = laserScanAt(kTruePose);
    EXPECT_LT(m.computeObservationLikelihood(laser, CPose3D(nan, 0, 0, 0, 0, 0)),
              m.computeObservationLikelihood(laser, kTruePose));
    // The label at a point no key can hold: nothing there.
    EXPECT_FALSE(map().core().labelAt({nan, 0, 0}).found);
    EXPECT_FALSE(map().core().labelAt({1e30, 0, 0}).found);
    EXPECT_FALSE(map().core().labelAt({0, std::numeric_limits<double>::infinity(), 0}).found);
    // MRPT's points map crashed on a NaN query point: a clear error instead.
    EXPECT_THROW(map().squareDistanceToClosestCorrespondence(float(nan), 0.f), std::invalid_argument);
}

TEST(LocalisationEmpty, EmptyMapGivesNoObstaclesAndAFlatLikelihood)
{
    PanopticNDTMap empty;
    EXPECT_EQ(empty.getAsSimplePointsMap()->size(), 0u);
    EXPECT_GT(empty.squareDistanceToClosestCorrespondence(0, 0), 1e9f);
    const auto obs = laserScanAt(kTruePose);
    EXPECT_EQ(empty.computeObservationLikelihood(obs, kTruePose), empty.computeObservationLikelihood(obs, CPose3D()));
}

INSTANTIATE_TEST_SUITE_P(BuiltAndLoaded, Localisation, ::testing::Values("built", "loaded"));
