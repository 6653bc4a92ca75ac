// ObservationPairer's frame recycling: a frame handed back takes the next scan in its own
// images (its label images kept apart for the next labelled frame), and nothing of what it
// held (labels, depth, pose, stamp) reaches the next frame.
#include <gtest/gtest.h>
#include <pndt/mrpt/observation_pairer.h>

#include "observation_fixtures.h"

using namespace pndt;

namespace
{
const mrpt::poses::CPose3D kRobot;

/// Pairs scan + labels of time t (labels when `labelled`) into exactly one frame.
PairedFrame pairOne(ObservationPairer& pairer, double t, float depth_m, bool labelled)
{
    std::vector<PairedFrame> done;
    pairer.push(*fixtures::wallScan(t, depth_m), kRobot, done);
    if (labelled)
    {
        pairer.push(*fixtures::semanticImage(t), kRobot, done);
        pairer.push(*fixtures::instanceImage(t), kRobot, done);
    }
    else
        pairer.flush(done);
    EXPECT_EQ(done.size(), 1u);
    return std::move(done.front());
}

/// The four label images of `got` hold what a fresh pairer's frame (`expected`) holds.
void expectSameLabels(const PanopticFrame& got, const PanopticFrame& expected)
{
    EXPECT_EQ(got.semantic.width, expected.semantic.width);
    EXPECT_EQ(got.semantic.height, expected.semantic.height);
    EXPECT_EQ(got.semantic.data, expected.semantic.data);
    EXPECT_EQ(got.semantic_score.data, expected.semantic_score.data);
    EXPECT_EQ(got.instance.data, expected.instance.data);
    EXPECT_EQ(got.panoptic_score.data, expected.panoptic_score.data);
}
}  // namespace

TEST(ObservationPairer, ARecycledFrameTakesTheNextScanInItsOwnImages)
{
    ObservationPairer pairer;
    PairedFrame first = pairOne(pairer, 0, 2.0f, true);
    ASSERT_TRUE(first.labelled);
    ASSERT_TRUE(first.frame.hasLabels());
    const float* depth_pixels = first.frame.depth.data.data();
    const uint16_t* semantic_pixels = first.frame.semantic.data.data();
    pairer.recycle(std::move(first));

    // Labelled again: the same buffers, the new scan's depth and the same labels as a new pairer's.
    PairedFrame second = pairOne(pairer, 1, 3.0f, true);
    EXPECT_EQ(second.frame.depth.data.data(), depth_pixels);
    EXPECT_EQ(second.frame.semantic.data.data(), semantic_pixels);
    ObservationPairer fresh;
    const PairedFrame expected = pairOne(fresh, 1, 3.0f, true);
    EXPECT_EQ(second.frame.depth.data, expected.frame.depth.data);
    expectSameLabels(second.frame, expected.frame);
    EXPECT_EQ(second.stamp, expected.stamp);
    EXPECT_FLOAT_EQ(second.frame.depth.at(5, 5), 3.0f);
}

TEST(ObservationPairer, ARecycledLabelledFrameLendsNoLabelsToAFrameWithout)
{
    ObservationPairer pairer;
    pairer.recycle(pairOne(pairer, 0, 2.0f, true));
    const PairedFrame bare = pairOne(pairer, 1, 2.5f, false);
    EXPECT_FALSE(bare.labelled);
    EXPECT_FALSE(bare.frame.hasLabels());
    EXPECT_FALSE(bare.frame.hasInstances());
    EXPECT_TRUE(bare.frame.semantic_score.empty());
    EXPECT_TRUE(bare.frame.panoptic_score.empty());
    EXPECT_FLOAT_EQ(bare.frame.depth.at(0, 0), 2.5f);
    EXPECT_EQ(bare.stamp, fixtures::stamp(1));
}

TEST(ObservationPairer, LabelImagesKeptThroughAFrameWithoutLabelsServeTheNextLabelledFrame)
{
    ObservationPairer pairer;
    PairedFrame first = pairOne(pairer, 0, 2.0f, true);
    const uint16_t* semantic_pixels = first.frame.semantic.data.data();
    const uint32_t* instance_pixels = first.frame.instance.data.data();
    const float* score_pixels = first.frame.panoptic_score.data.data();
    pairer.recycle(std::move(first));
    PairedFrame bare = pairOne(pairer, 1, 2.5f, false);
    EXPECT_FALSE(bare.frame.hasLabels());
    // The label images were kept apart at their size, not emptied inside the frame (a vector
    // grown back from empty zero-fills every pixel before the decode overwrites it).
    EXPECT_EQ(bare.frame.semantic.data.capacity(), 0u);
    EXPECT_EQ(bare.frame.panoptic_score.data.capacity(), 0u);
    pairer.recycle(std::move(bare));  // a frame without labels leaves the kept label images alone
    const PairedFrame third = pairOne(pairer, 2, 3.0f, true);
    EXPECT_EQ(third.frame.semantic.data.data(), semantic_pixels);
    EXPECT_EQ(third.frame.instance.data.data(), instance_pixels);
    EXPECT_EQ(third.frame.panoptic_score.data.data(), score_pixels);
    ObservationPairer fresh;
    const PairedFrame expected = pairOne(fresh, 2, 3.0f, true);
    expectSameLabels(third.frame, expected.frame);
}

TEST(ObservationPairer, ACopyPairsAsTheOriginalButTakesNoSpareFrame)
{
    ObservationPairer pairer;
    PairedFrame used = pairOne(pairer, 0, 2.0f, true);
    const float* spare_pixels = used.frame.depth.data.data();
    pairer.recycle(std::move(used));
    std::vector<PairedFrame> done;
    pairer.push(*fixtures::semanticImage(1), kRobot, done);  // labels before their depth
    ObservationPairer copy(pairer);
    copy.push(*fixtures::instanceImage(1), kRobot, done);
    copy.push(*fixtures::wallScan(1), kRobot, done);
    ASSERT_EQ(done.size(), 1u);
    EXPECT_TRUE(done.front().labelled);
    EXPECT_NE(done.front().frame.depth.data.data(), spare_pixels);  // the original keeps its spare
    EXPECT_EQ(pairer.labelImagesWaiting(), 1u);                      // and its own labels
    pairer.push(*fixtures::instanceImage(1), kRobot, done);
    pairer.push(*fixtures::wallScan(1), kRobot, done);
    ASSERT_EQ(done.size(), 2u);
    EXPECT_EQ(done.back().frame.depth.data.data(), spare_pixels);
    EXPECT_EQ(done.back().frame.semantic.data, done.front().frame.semantic.data);
}

TEST(ObservationPairer, AScanThatFailsToConvertLeavesNothingPendingAfterARecycledFrame)
{
    ObservationPairer pairer;
    pairer.recycle(pairOne(pairer, 0, 2.0f, true));
    auto bad = fixtures::wallScan(1);
    bad->cameraParams.fx(0);  // invalid intrinsics
    std::vector<PairedFrame> done;
    EXPECT_THROW(pairer.push(*bad, kRobot, done), InputError);
    EXPECT_FALSE(pairer.hasPending());
    pairer.flush(done);
    EXPECT_TRUE(done.empty());  // no half-converted frame comes out later
    const PairedFrame next = pairOne(pairer, 2, 2.5f, false);
    EXPECT_FLOAT_EQ(next.frame.depth.at(3, 3), 2.5f);
}
