// PoseInterpolator: SLERP/LERP, exact hits, range and gap limits, ordering checks.
#include "io_test_util.h"

#include <pndt/io/pose_interpolator.h>

#include <cmath>

namespace pndt::io::test
{
namespace
{
constexpr double kPi = 3.14159265358979323846;

StampedPose yawPose(double t, double yaw, Eigen::Vector3d xyz)
{
    StampedPose p;
    p.t = t;
    p.T_world_sensor = Pose::Identity();
    p.T_world_sensor.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    p.T_world_sensor.translation() = xyz;
    return p;
}

double yawOf(const Pose& T) { return std::atan2(T.linear()(1, 0), T.linear()(0, 0)); }
}  // namespace

TEST(PoseInterpolator, SlerpMidpointOfZeroAndNinetyDegreesYawIsFortyFive)
{
    const PoseInterpolator ip({yawPose(10.0, 0.0, {0, 0, 0}), yawPose(11.0, kPi / 2, {2, -4, 1})});
    const auto mid = ip.at(10.5, 2.0);
    ASSERT_TRUE(mid.has_value());
    EXPECT_NEAR(yawOf(*mid), kPi / 4, 1e-12);
    EXPECT_TRUE(mid->translation().isApprox(Eigen::Vector3d(1, -2, 0.5), 1e-12));
    // Pure yaw stays pure yaw.
    EXPECT_NEAR((mid->rotation() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitZ()).norm(), 0, 1e-12);
    const auto q = ip.at(10.25, 2.0);
    ASSERT_TRUE(q.has_value());
    EXPECT_NEAR(yawOf(*q), kPi / 8, 1e-12);
    EXPECT_TRUE(q->translation().isApprox(Eigen::Vector3d(0.5, -1, 0.25), 1e-12));
}

TEST(PoseInterpolator, ShortestArcAcrossPlusMinusPi)
{
    const PoseInterpolator ip({yawPose(0.0, kPi - 0.1, {0, 0, 0}), yawPose(1.0, -kPi + 0.1, {0, 0, 0})});
    const auto mid = ip.at(0.5, 1.0);
    ASSERT_TRUE(mid.has_value());
    EXPECT_NEAR(std::abs(yawOf(*mid)), kPi, 1e-9);  // through 180°, not through 0°
}

TEST(PoseInterpolator, ExactHitReturnsStoredPose)
{
    auto a = yawPose(1.0, 0.3, {1, 2, 3});
    auto b = yawPose(5.0, -1.2, {4, 5, 6});
    auto c = yawPose(5.5, 0.7, {7, 8, 9});
    const PoseInterpolator ip({a, b, c});
    // Exact hits ignore max_gap (the stored pose is not stale).
    EXPECT_EQ(ip.at(5.0, 0.01)->matrix(), b.T_world_sensor.matrix());
    EXPECT_EQ(ip.at(1.0, 0.0)->matrix(), a.T_world_sensor.matrix());
    EXPECT_EQ(ip.at(5.5, 0.0)->matrix(), c.T_world_sensor.matrix());
}

TEST(PoseInterpolator, OutsideRangeOrGapTooLargeGivesNullopt)
{
    const PoseInterpolator ip({yawPose(1.0, 0, {0, 0, 0}), yawPose(2.0, 0, {1, 0, 0}),
                               yawPose(4.0, 0, {3, 0, 0})});
    EXPECT_FALSE(ip.at(0.999, 10).has_value());
    EXPECT_FALSE(ip.at(4.001, 10).has_value());
    EXPECT_FALSE(ip.at(std::nan(""), 10).has_value());
    EXPECT_TRUE(ip.at(1.5, 1.0).has_value());   // gap 1.0 <= 1.0
    EXPECT_FALSE(ip.at(3.0, 1.5).has_value());  // gap 2.0 > 1.5
    ASSERT_TRUE(ip.at(3.0, 2.0).has_value());
    EXPECT_NEAR(ip.at(3.0, 2.0)->translation().x(), 2.0, 1e-12);
    EXPECT_FALSE(PoseInterpolator().at(1.0, 1.0).has_value());
    EXPECT_EQ(ip.size(), 3u);
    EXPECT_EQ(ip.startTime(), 1.0);
    EXPECT_EQ(ip.endTime(), 4.0);
}

TEST(PoseInterpolator, OutOfOrderOrDuplicateStampsThrowNamingTheIndex)
{
    EXPECT_INPUT_ERROR(PoseInterpolator({yawPose(1, 0, {0, 0, 0}), yawPose(2, 0, {0, 0, 0}), yawPose(1.5, 0, {0, 0, 0})}),
                       "pose 2", "out of order");
    EXPECT_INPUT_ERROR(PoseInterpolator({yawPose(1, 0, {0, 0, 0}), yawPose(1, 0, {0, 0, 0})}), "pose 1", "duplicate");
    EXPECT_INPUT_ERROR(PoseInterpolator({yawPose(std::nan(""), 0, {0, 0, 0})}), "pose 0", "non-finite");
}

TEST(PoseInterpolator, ForgetBeforeKeepsEveryAnswerFromThatTimeOn)
{
    // 5000 poses at 30 Hz, turning and moving: the full track and one that forgets.
    PoseInterpolator all, kept;
    const auto poseAt = [](int k) { return yawPose(100.0 + k / 30.0, 0.01 * k, {0.002 * k, std::sin(0.01 * k), 0}); };
    for (int k = 0; k < 5000; ++k)
    {
        all.append(poseAt(k));
        kept.append(poseAt(k));
    }
    // Fewer than 1024 poses to drop: nothing moves.
    kept.forgetBefore(100.0 + 1000.5 / 30.0);
    EXPECT_EQ(kept.size(), 5000u);
    // Poses 0..2999 lie before pose 3000, the last one at or before t: they go.
    const double t = 100.0 + 3000.5 / 30.0;
    kept.forgetBefore(t);
    EXPECT_EQ(kept.size(), 2000u);
    EXPECT_EQ(kept.appended(), 5000u);
    EXPECT_EQ(kept.startTime(), all.poses()[3000].t);
    // From t on (between stamps, on them, to the end) the same answers, to the bit.
    for (double q = t; q <= all.endTime(); q += 0.0123)
    {
        const auto a = all.at(q, 0.1), b = kept.at(q, 0.1);
        ASSERT_TRUE(a.has_value()) << q;
        ASSERT_TRUE(b.has_value()) << q;
        EXPECT_EQ(a->matrix(), b->matrix()) << q;
    }
    EXPECT_EQ(kept.at(all.poses()[4000].t, 0.0)->matrix(), all.poses()[4000].T_world_sensor.matrix());
    // Before the poses kept: no pose (a frame that far back is skipped).
    EXPECT_FALSE(kept.at(all.poses()[2999].t, 0.1).has_value());
    // Appending goes on, and errors count the forgotten poses.
    kept.append(poseAt(5000));
    EXPECT_INPUT_ERROR(kept.append(poseAt(4999)), "pose 5001", "out of order");
}

TEST(PoseInterpolator, InterpolatePoseHelper)
{
    const auto a = yawPose(0, 0, {0, 0, 0}).T_world_sensor;
    const auto b = yawPose(0, kPi / 2, {2, 0, 0}).T_world_sensor;
    EXPECT_EQ(interpolatePose(a, b, 0.0).matrix(), a.matrix());
    EXPECT_NEAR(yawOf(interpolatePose(a, b, 0.5)), kPi / 4, 1e-12);
}

}  // namespace pndt::io::test

TEST(PoseInterpolatorGap, TenHertzPosesAtUnixStampsPassAMaxGapOfOneTenth)
{
    // 1.3e9 + 0.1 - 1.3e9 computes as 0.10000002: rounding must not reject it.
    std::vector<pndt::io::StampedPose> poses(2);
    poses[0].t = 1.3e9 + 0.1;
    poses[1].t = 1.3e9 + 0.2;
    poses[0].T_world_sensor = poses[1].T_world_sensor = pndt::Pose::Identity();
    const pndt::io::PoseInterpolator interp(poses);
    EXPECT_TRUE(interp.at(1.3e9 + 0.15, 0.1).has_value());
    EXPECT_FALSE(interp.at(1.3e9 + 0.15, 0.09).has_value());
}
