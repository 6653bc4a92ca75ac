// StampOrder: the order of a camera's frame stamps and a device clock that was reset, with
// stamps and arrival times written out by hand (30 frames/s, frames arriving 20 ms after
// their stamps on a host clock 1000 s ahead of the camera's).
#include <gtest/gtest.h>
#include <pndt/live/stamp_order.h>

using pndt::live::StampOrder;
using V = StampOrder::Verdict;

namespace
{
constexpr double kDt = 1.0 / 30, kHostAhead = 1000.0, kDelay = 0.020;
double arrivalOf(int k) { return kHostAhead + k * kDt + kDelay; }  // frame k's arrival
}  // namespace

TEST(StampOrder, FramesInOrderAreTaken)
{
    StampOrder o(true, 2.0);
    for (int k = 0; k < 40; ++k)
    {
        EXPECT_EQ(o.next(k * kDt, arrivalOf(k)), V::take) << k;
        EXPECT_TRUE(o.message().empty()) << o.message();
    }
}

TEST(StampOrder, AFrameDeliveredOutOfOrderIsDroppedAndTheNextGoesOn)
{
    StampOrder o(true, 2.0);
    for (int k = 0; k < 30; ++k) ASSERT_EQ(o.next(k * kDt, arrivalOf(k)), V::take);
    // Frame 30 carries frame 25's stamp: dropped, the gap said once.
    EXPECT_EQ(o.next(25 * kDt, arrivalOf(30)), V::drop);
    EXPECT_NE(o.message().find("went back"), std::string::npos) << o.message();
    // Frame 31 is on time: taken, the gap ends, no reset.
    EXPECT_EQ(o.next(31 * kDt, arrivalOf(31)), V::take);
    EXPECT_NE(o.message().find("in order again at t=1.033333 s"), std::string::npos) << o.message();
    EXPECT_EQ(o.next(32 * kDt, arrivalOf(32)), V::take);
}

TEST(StampOrder, AClockResetWhoseStampsPassTheOldOnesIsAResetNotAGap)
{
    StampOrder o(true, 2.0);
    for (int k = 0; k < 30; ++k) ASSERT_EQ(o.next(k * kDt, arrivalOf(k)), V::take);
    // From frame 30 on the device clock starts again at 0: frame k is stamped (k - 30) / 30.
    for (int k = 30; k < 60; ++k) ASSERT_EQ(o.next((k - 30) * kDt, arrivalOf(k)), V::drop) << k;
    // Frame 60 (t = 1 s) passes frame 29's stamp, but 1 s behind the host clock.
    EXPECT_EQ(o.next(30 * kDt, arrivalOf(60)), V::clock_reset);
    EXPECT_NE(o.message().find("clock was reset"), std::string::npos) << o.message();
    EXPECT_NE(o.message().find("1.000 s behind the host clock"), std::string::npos) << o.message();
}

TEST(StampOrder, ALagJustUnderTheLimitIsTakenAndJustOverIsAReset)
{
    for (const double lag : {StampOrder::kResetLag - 0.01, StampOrder::kResetLag + 0.01})
    {
        StampOrder o(true, 2.0);
        for (int k = 0; k < 30; ++k) ASSERT_EQ(o.next(k * kDt, arrivalOf(k)), V::take);
        ASSERT_EQ(o.next(28 * kDt, arrivalOf(30) + lag), V::drop);
        EXPECT_EQ(o.next(31 * kDt, arrivalOf(31) + lag), lag < StampOrder::kResetLag ? V::take : V::clock_reset)
            << lag;
    }
}

TEST(StampOrder, HostStampsAreOnlyCheckedForOrder)
{
    // The same reset as above with host stamps (an NTP step, say): no lag to measure.
    StampOrder o(false, 2.0);
    for (int k = 0; k < 30; ++k) ASSERT_EQ(o.next(k * kDt, arrivalOf(k)), V::take);
    for (int k = 30; k < 60; ++k) ASSERT_EQ(o.next((k - 30) * kDt, arrivalOf(k)), V::drop);
    EXPECT_EQ(o.next(30 * kDt, arrivalOf(60)), V::take);
}

TEST(StampOrder, StampsThatStayBehindLongerThanTheGapLimitLoseTheCamera)
{
    StampOrder o(true, 0.5);
    for (int k = 0; k < 30; ++k) ASSERT_EQ(o.next(k * kDt, arrivalOf(k)), V::take);
    // The clock starts again at 0 at frame 30; 0.5 s later (frame 45) the camera is lost.
    for (int k = 30; k < 45; ++k) ASSERT_EQ(o.next((k - 30) * kDt, arrivalOf(k)), V::drop) << k;
    EXPECT_EQ(o.next(15 * kDt, arrivalOf(45)), V::clock_reset);
    EXPECT_NE(o.message().find("did not pass t=0.966667 s again within 0.5 s"), std::string::npos) << o.message();
}

TEST(StampOrder, AClockThatJumpsAheadLosesTheCamera)
{
    // From frame 40 on the device clock runs 30 frames (1 s) ahead: its frames would wait for
    // the poses of 1 s later and take them (a jump under --pose-wait), or all wait in vain.
    StampOrder o(true, 2.0);
    for (int k = 0; k < 40; ++k) ASSERT_EQ(o.next(k * kDt, arrivalOf(k)), V::take) << k;
    EXPECT_EQ(o.next((40 + 30) * kDt, arrivalOf(40)), V::clock_reset);
    EXPECT_NE(o.message().find("clock jumped 1.000 s ahead of the host clock (t=2.333333 s after t=1.300000 s)"),
              std::string::npos)
        << o.message();
}

TEST(StampOrder, AJumpJustUnderTheLimitIsTakenAndJustOverLosesTheCamera)
{
    for (const double jump : {StampOrder::kJumpAhead - 0.01, StampOrder::kJumpAhead + 0.01})
    {
        StampOrder o(true, 2.0);
        for (int k = 0; k < 40; ++k) ASSERT_EQ(o.next(k * kDt, arrivalOf(k)), V::take);
        EXPECT_EQ(o.next(40 * kDt + jump, arrivalOf(40)), jump < StampOrder::kJumpAhead ? V::take : V::clock_reset)
            << jump;
    }
}

TEST(StampOrder, LateFramesThenOnTimeOnesAreNoJump)
{
    // A stalled reader: frames 10-19 arrive 0.6 s late, then delivery is on time again. The
    // least delay of the last 32 frames is the on-time one: nothing jumped.
    StampOrder o(true, 2.0);
    for (int k = 0; k < 60; ++k)
        EXPECT_EQ(o.next(k * kDt, arrivalOf(k) + (k >= 10 && k < 20 ? 0.6 : 0.0)), V::take) << k;
    // Before 32 frames are seen there is no least delay to judge by: no verdict either way.
    StampOrder young(true, 2.0);
    for (int k = 0; k < 31; ++k) ASSERT_EQ(young.next(k * kDt, arrivalOf(k) + 0.6), V::take);
    EXPECT_EQ(young.next(31 * kDt, arrivalOf(31)), V::take);
    // Host stamps: no clock to judge.
    StampOrder host(false, 2.0);
    for (int k = 0; k < 40; ++k) ASSERT_EQ(host.next(k * kDt, arrivalOf(k)), V::take);
    EXPECT_EQ(host.next(70 * kDt, arrivalOf(40)), V::take);
}
