// PoseTrack as the mappers feed it for hours (pndt-live's localiser, a long rawlog's robot
// poses): the poses behind the frames are let go of, and every frame gets the pose the whole
// track gives it.
#include <gtest/gtest.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <pndt/app/pose_track.h>

#include <algorithm>
#include <cmath>

namespace pndt::app::test
{
TEST(PoseTrack, ATrackFedForAnHourStaysSmallAndPlacesEveryFrameAsTheWholeTrack)
{
    PoseTrack live = PoseTrack::whileReading("the test stream", "", 0.1);
    PoseTrack whole = PoseTrack::whileReading("the test stream", "", 0.1);
    const mrpt::poses::CPose3D extrinsic(0.1, 0, 0.5, -M_PI / 2, 0, -M_PI / 2);
    constexpr int kPoses = 3600 * 30;  // an hour of a 30 Hz localiser
    size_t most = 0, frames = 0;
    for (int k = 0; k < kPoses; ++k)
    {
        mrpt::obs::CObservationRobotPose p;
        p.timestamp = mrpt::Clock::fromDouble(1.7e9 + k / 30.0);
        p.pose.mean = mrpt::poses::CPose3D(std::cos(1e-3 * k), std::sin(1e-3 * k), 0, 1e-3 * k, 0, 0);
        ASSERT_TRUE(live.addRobotPose(p));
        ASSERT_TRUE(whole.addRobotPose(p));
        if (k % 3 != 2) continue;
        // A 10 Hz camera's frame between the last two poses, as the mapper places it.
        const double t = 1.7e9 + (k - 0.5) / 30.0;
        const auto a = live.cameraAt(t, extrinsic), b = whole.cameraAt(t, extrinsic);
        ASSERT_TRUE(a.has_value()) << k;
        ASSERT_TRUE(b.has_value()) << k;
        ASSERT_EQ(a->matrix(), b->matrix()) << k;
        ++frames;
        live.forgetBefore(t - PoseTrack::kKeptSeconds);
        most = std::max(most, live.size());
    }
    EXPECT_EQ(frames, size_t(kPoses / 3));
    EXPECT_EQ(whole.size(), size_t(kPoses));
    // The last kKeptSeconds of poses, and at most as many again before they are let go of.
    const size_t window = size_t(PoseTrack::kKeptSeconds * 30);
    EXPECT_GE(most, window);
    EXPECT_LE(most, 2 * window + 4);
    // A frame further back than that finds no pose (it is skipped, never placed with a stale one).
    EXPECT_FALSE(live.cameraAt(1.7e9 + 1.0, extrinsic).has_value());
    EXPECT_TRUE(whole.cameraAt(1.7e9 + 1.0, extrinsic).has_value());
}

}  // namespace pndt::app::test
