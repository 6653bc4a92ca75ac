// 16-bit histogram weights with a shared scale (histogram_weights.h), tested
// in every build: the template does not depend on PNDT_QUANTISED_HISTOGRAMS.
#include <gtest/gtest.h>
#include <pndt/sparse_histogram.h>

#include <cmath>
#include <cstring>

using namespace pndt;
using QuantisedHist = SparseHistogram<uint8_t, 8, QuantisedWeights<8>>;
using FloatHist = SparseHistogram<uint8_t, 8, FloatWeights<8>>;

TEST(QuantisedWeights, ValuesOnTheScaleAreStoredExactlyAndTheScaleGrowsByHalving)
{
    QuantisedHist h;
    h.add(3, 0.5f);  // 0.5 * 2^16 = 32768 steps of 2^-16
    EXPECT_EQ(h.weights.m[0], 32768);
    EXPECT_EQ(h.weights.exponent, -16);
    EXPECT_EQ(h.weight(0), 0.5f);
    h.add(3, 0.75f);  // 1.25 needs 81920 steps: one halving, 40960 steps of 2^-15
    EXPECT_EQ(h.weights.exponent, -15);
    EXPECT_EQ(h.weights.m[0], 40960);
    EXPECT_EQ(h.weight(0), 1.25f);
    // 0.1 = 3276.8 steps; third write: d = (3 * 40503 >> 8) mod 256 = 218,
    // dither 437 / 512 = 0.85 carries the 0.8 -> 3277.
    h.add(4, 0.1f);
    EXPECT_EQ(h.weights.m[1], 3277);
    EXPECT_EQ(h.weight(1), 3277.f / 32768.f);
    EXPECT_EQ(h.ids[0], 3);
    EXPECT_EQ(h.ids[1], 4);
    EXPECT_EQ(h.sum(), (40960.f + 3277.f) / 32768.f);
    EXPECT_EQ(sizeof(QuantisedHist), 28u);  // 8 ids, 8 x 16 bits, scale, dither counter
}

TEST(QuantisedWeights, ARescaleByManyStepsKeepsTheOrderAndRoundsTheOthers)
{
    QuantisedHist h;
    for (uint8_t id = 1; id <= 8; ++id) h.add(id, 0.9f - 0.1f * float(id - 1));  // 0.9 ... 0.2
    h.add(8, 1000.f);  // 1000.2: 2^-16 -> 2^-6 (ten halvings), 8 moves to the front
    EXPECT_EQ(h.weights.exponent, -6);
    EXPECT_EQ(h.ids[0], 8);
    EXPECT_NEAR(h.weight(0), 1000.2f, 1.f / 64.f);
    // 0.9 = 58982 steps of 2^-16 -> 58982 / 1024 = 57.6 -> 58 steps of 2^-6.
    EXPECT_EQ(h.weight(1), 58.f / 64.f);
    for (int i = 1; i < h.size(); ++i) EXPECT_GE(h.weight(i - 1), h.weight(i)) << i;
    // Each within half a step of 2^-6 (plus the first rounding, 2^-16).
    for (int i = 1; i < h.size(); ++i) EXPECT_NEAR(h.weight(i), 1.0f - 0.1f * float(i), 0.008f) << i;
}

// A voxel watched for long: 300 000 one-pixel updates. Rounded to the nearest
// step, every update below half a step would be lost once the total passes
// 2^16 steps of 1.4: entry 1 would stop at 29 % of its sum (simulated).
TEST(QuantisedWeights, LongSumsOfSmallUpdatesStayWithinAFractionOfAPercent)
{
    QuantisedHist q;
    FloatHist f;
    double exact1 = 0, exact2 = 0, exact3 = 0;
    for (int k = 0; k < 300000; ++k)
    {
        const float s = 0.55f + 0.4f * float((k % 1000) * 7919 % 1000) / 1000.f;  // scores in [0.55, 0.95)
        q.add(1, s);
        f.add(1, s);
        exact1 += s;
        if (k % 3 == 0)
        {
            q.add(2, s);
            exact2 += s;
        }
        if (k % 97 == 0)
        {
            q.add(3, 0.6f);
            exact3 += 0.6;
        }
    }
    ASSERT_EQ(q.ids[0], 1);
    ASSERT_EQ(q.ids[1], 2);
    ASSERT_EQ(q.ids[2], 3);
    EXPECT_NEAR(q.weight(0) / exact1, 1.0, 2e-3);
    EXPECT_NEAR(q.weight(1) / exact2, 1.0, 2e-3);
    EXPECT_NEAR(q.weight(2) / exact3, 1.0, 2e-2);  // 3093 updates of 0.6 at a step of 4
    EXPECT_NEAR(q.weight(1) / q.weight(0), exact2 / exact1, 2e-3);
    // The float histogram on the same updates, for comparison.
    EXPECT_NEAR(f.weight(0) / exact1, 1.0, 2e-3);
}

TEST(QuantisedWeights, TheLargestFiniteWeightsAreStoredToSixteenBits)
{
    QuantisedHist h;  // e.g. read from a map file: any finite weight >= 0 is accepted
    h.add(1, 3e38f);
    h.add(2, 1.f);  // far below the step: 0
    EXPECT_EQ(h.weights.exponent, 112);  // 3e38 < 2^128 = 2^16 * 2^112
    EXPECT_NEAR(h.weight(0) / 3e38f, 1.f, 1.f / 32768.f);
    EXPECT_EQ(h.weight(1), 0.f);
    EXPECT_EQ(h.ids[1], 2);
}

TEST(QuantisedWeights, TheSameWritesGiveTheSameBits)
{
    QuantisedHist a, b;
    for (int k = 0; k < 5000; ++k)
    {
        a.add(uint8_t(1 + k % 5), 0.3f + 0.001f * float(k % 600));
        b.add(uint8_t(1 + k % 5), 0.3f + 0.001f * float(k % 600));
    }
    EXPECT_EQ(0, std::memcmp(a.weights.m, b.weights.m, sizeof(a.weights.m)));
    EXPECT_EQ(a.weights.exponent, b.weights.exponent);
}
