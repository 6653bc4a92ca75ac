// The map inside MRPT's own particle-filter localiser (CMonteCarloLocalization2D):
// a robot with a 2D laser drives 2 m through the two-table room; started from
// particles spread over 1.2 x 1.2 m and ±30°, the estimate ends near the true pose.
#include <gtest/gtest.h>
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/slam/CMonteCarloLocalization2D.h>
#include <pndt/sim/raycast.h>

#include "nav_test_scene.h"

using namespace pndt;
using mrpt::poses::CPose2D;

namespace
{
mrpt::obs::CObservation2DRangeScan::Ptr laserScanAt(const CPose2D& robot)
{
    auto s = mrpt::obs::CObservation2DRangeScan::Create();
    s->sensorLabel = "LASER";
    s->sensorPose = mrpt::poses::CPose3D(0, 0, 0.3, 0, 0, 0);
    s->aperture = float(M_PI);
    s->rightToLeft = true;
    s->maxRange = 20;
    s->resizeScan(91);
    const mrpt::poses::CPose3D sensor = mrpt::poses::CPose3D(robot) + s->sensorPose;
    for (size_t i = 0; i < 91; ++i)
    {
        double x, y, z;
        const double a = s->getScanAngle(i);
        sensor.composePoint(std::cos(a), std::sin(a), 0.0, x, y, z);
        const Eigen::Vector3d o(sensor.x(), sensor.y(), sensor.z());
        const sim::RayHit h = sim::castRay(navtest::scene(), o, Eigen::Vector3d(x, y, z) - o, 20.0);
        s->setScanRange(i, h.hit ? float(h.t) : 0.f);
        s->setScanRangeValidity(i, h.hit);
    }
    return s;
}
}  // namespace

TEST(MonteCarloLocalization, ConvergesOnTheMapFromAWideStart)
{
    mrpt::random::getRandomGenerator().randomize(7);
    auto map = std::make_shared<PanopticNDTMap>(navtest::builtMap());
    map->navigationOptions.likelihood.outlier_mahalanobis_sq = 4;  // a softer score for few particles
    mrpt::slam::CMonteCarloLocalization2D pdf(3000);
    pdf.options.metricMap = map;
    CPose2D truth(0.2, -2.2, M_PI / 2);
    pdf.resetUniform(truth.x() - 0.6, truth.x() + 0.6, truth.y() - 0.6, truth.y() + 0.6, truth.phi() - 0.5,
                     truth.phi() + 0.5);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.PF_algorithm = mrpt::bayes::CParticleFilter::pfStandardProposal;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions motion;
    motion.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
    motion.gaussianModel.minStdXY = 0.03;
    motion.gaussianModel.minStdPHI = 2 * M_PI / 180;
    const CPose2D step(0.2, 0, 0);  // 10 steps of 20 cm up the room
    for (int k = 0; k < 10; ++k)
    {
        truth = truth + step;
        mrpt::obs::CActionCollection acts;
        mrpt::obs::CActionRobotMovement2D move;
        move.computeFromOdometry(step, motion);
        acts.insert(move);
        mrpt::obs::CSensoryFrame sf;
        sf.insert(laserScanAt(truth));
        pf.executeOn(pdf, &acts, &sf);
    }
    CPose2D estimate;
    pdf.getMean(estimate);
    std::cout << "  truth " << truth << ", estimate " << estimate << "\n";
    EXPECT_NEAR(estimate.x(), truth.x(), 0.1);
    EXPECT_NEAR(estimate.y(), truth.y(), 0.1);
    EXPECT_NEAR(std::remainder(estimate.phi() - truth.phi(), 2 * M_PI), 0, 5 * M_PI / 180);
}
