// The camera / localiser time offset estimate: a known offset on a curved path is found
// within its standard error, no offset gives ~0, drift (a slow position offset) does not
// bias it, a straight line at constant speed is not observable, too few frames refuse.
#include <gtest/gtest.h>
#include <pndt/refine/time_offset.h>

#include <cmath>
#include <random>

namespace
{
using pndt::Pose;
using pndt::refine::TimeOffsetEstimator;

/// A hand-held camera's path: a figure of eight at walking speed, velocity changing within a
/// second (the estimate removes each second's mean and drift rate).
Eigen::Vector3d curved(double t) { return {0.8 * std::sin(1.5 * t), 0.5 * std::sin(2.5 * t), 1.2 + 0.05 * std::sin(0.9 * t)}; }
Eigen::Vector3d straight(double t) { return {0.5 * t, 0.2 * t, 1.2}; }

Pose at(const Eigen::Vector3d& p)
{
    Pose T = Pose::Identity();
    T.translation() = p;
    return T;
}

/// Frames at 30 Hz for `seconds`; the localiser's pose stamped s is the truth at s + delta
/// (+ drift of `drift` m/s along x), the refined poses are the truth + N(0, noise).
TimeOffsetEstimator feed(Eigen::Vector3d (*path)(double), double delta, double seconds, double noise, double drift = 0,
                         unsigned seed = 1)
{
    TimeOffsetEstimator est;
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, noise);
    for (int i = 0; double(i) / 30.0 < seconds; ++i)
    {
        const double t = 100.0 + i / 30.0;
        const Eigen::Vector3d truth = path(t);
        // What the app interpolated for camera time t: the truth at t - delta (the localiser
        // is late by delta), so the truth at t is that track at t + delta.
        const Eigen::Vector3d external = path(t - delta) + Eigen::Vector3d(drift * (t - 100.0), 0, 0);
        est.add(t, at(external), at(truth + Eigen::Vector3d(n(rng), n(rng), n(rng))), i % 7 != 3);
    }
    return est;
}
}  // namespace

TEST(TimeOffset, FindsAKnownOffsetOnACurvedPath)
{
    // External E(t) = truth(t - 0.04): the truth at camera time t is E(t + 0.04), offset +40 ms.
    for (double delta : {0.04, -0.025, 0.1})
    {
        const auto e = feed(curved, delta, 20.0, 0.003).estimate();
        ASSERT_TRUE(e.valid) << e.reason;
        EXPECT_NEAR(e.offset, delta, 0.002) << e.summary();
        EXPECT_LT(e.standard_error, 0.002);
        EXPECT_LT(e.rms_after, e.rms_before);
        EXPECT_NEAR(e.rms_after, 0.003 * std::sqrt(3.0), 0.001);  // what is left: the refined poses' noise (3 axes)
    }
}

TEST(TimeOffset, NoOffsetGivesZeroAndDriftDoesNotBiasIt)
{
    const auto e = feed(curved, 0.0, 20.0, 0.003, 0.02).estimate();  // 2 cm/s drift: 40 cm over the run
    ASSERT_TRUE(e.valid) << e.reason;
    EXPECT_NEAR(e.offset, 0.0, 0.002) << e.summary();
    const auto d = feed(curved, 0.05, 20.0, 0.003, 0.02).estimate();
    ASSERT_TRUE(d.valid) << d.reason;
    EXPECT_NEAR(d.offset, 0.05, 0.003) << d.summary();
}

TEST(TimeOffset, AStraightLineAtConstantSpeedIsNotObservable)
{
    const auto e = feed(straight, 0.05, 20.0, 0.003).estimate();
    EXPECT_FALSE(e.valid);
    EXPECT_NE(e.reason.find("velocity"), std::string::npos) << e.reason;
}

TEST(TimeOffset, TooFewFramesOrAnOffsetBeyondTheLimitAreRefused)
{
    const auto e = feed(curved, 0.04, 0.5, 0.003).estimate();  // 15 frames
    EXPECT_FALSE(e.valid);
    EXPECT_NE(e.reason.find("needed"), std::string::npos) << e.reason;
    pndt::refine::TimeOffsetOptions o;
    o.max_offset = 0.05;
    TimeOffsetEstimator est(o);
    for (int i = 0; i < 600; ++i)
    {
        const double t = i / 30.0;
        est.add(t, at(curved(t - 0.2)), at(curved(t)), true);
    }
    const auto b = est.estimate();
    EXPECT_FALSE(b.valid);
    EXPECT_NE(b.reason.find("beyond"), std::string::npos) << b.reason;
}

TEST(TimeOffset, OutOfOrderStampsAreIgnored)
{
    TimeOffsetEstimator est;
    est.add(1.0, Pose::Identity(), Pose::Identity(), true);
    est.add(0.5, Pose::Identity(), Pose::Identity(), true);
    est.add(1.0, Pose::Identity(), Pose::Identity(), true);
    est.add(std::nan(""), Pose::Identity(), Pose::Identity(), true);
    EXPECT_EQ(est.size(), 1u);
}
