// Sparse histograms and the per-voxel predicates (paper Eq. 2-10), by hand.
#include <gtest/gtest.h>
#include <pndt/instance_rules.h>

#include <random>

using namespace pndt;
using InstanceHist = InstanceHistogram;

TEST(SparseHistogram, KeepsEntriesSortedByWeight)
{
    InstanceHist h;
    h.add(7, 1.f);
    h.add(9, 3.f);
    h.add(7, 2.5f);  // 7 now weighs 3.5 and moves ahead of 9
    ASSERT_EQ(h.size(), 2);
    EXPECT_EQ(h.ids[0], 7u);
    EXPECT_FLOAT_EQ(h.weight(0), 3.5f);
    EXPECT_EQ(h.ids[1], 9u);
    EXPECT_FLOAT_EQ(h.sum(), 6.5f);
    EXPECT_EQ(h.top(), 7u);
}

TEST(SparseHistogram, SeventeenthInstanceReplacesTheSmallestEntry)
{
    InstanceHist h;
    for (uint32_t id = 1; id <= 16; ++id) h.add(id, float(id));  // id 1 weighs least
    ASSERT_EQ(h.size(), 16);
    EXPECT_FLOAT_EQ(h.sum(), 136.f);  // 1+..+16
    float evicted_w = -1;
    const uint32_t evicted = h.add(100, 2.5f, &evicted_w);
    EXPECT_EQ(evicted, 1u);
    EXPECT_FLOAT_EQ(evicted_w, 1.f);
    EXPECT_EQ(h.size(), 16);
    EXPECT_EQ(h.indexOf(1), -1);
    // 2.5 sorts between ids 3 (w=3) and 2 (w=2): second to last.
    EXPECT_EQ(h.ids[14], 100u);
    EXPECT_EQ(h.ids[15], 2u);
    EXPECT_FLOAT_EQ(h.sum(), 136.f - 1.f + 2.5f);
    for (int i = 1; i < h.size(); ++i) EXPECT_GE(h.weight(i - 1), h.weight(i));
}

TEST(SparseHistogram, TiesKeepTheOlderEntryFirst)
{
    InstanceHist h;
    h.add(4, 2.f);
    h.add(5, 2.f);
    EXPECT_EQ(h.ids[0], 4u);
}

TEST(InstanceRules, IsInTopZOnAGivenHistogram)
{
    InstanceHist h;  // weights 5, 2, 1 (sum 8); theta_b = 0.8 -> ascending mass >= 1.6
    h.add(10, 5.f);
    h.add(20, 2.f);
    h.add(30, 1.f);
    EXPECT_TRUE(isInTopZ(h, 10, 0.8));   // cum 8
    EXPECT_TRUE(isInTopZ(h, 20, 0.8));   // cum 3 >= 1.6
    EXPECT_FALSE(isInTopZ(h, 30, 0.8));  // cum 1 < 1.6
    EXPECT_FALSE(isInTopZ(h, 99, 0.8));  // absent
    // theta_b = 0.95 -> threshold 0.4: every entry is in the top set.
    EXPECT_TRUE(isInTopZ(h, 30, 0.95));
    // theta_b = 0.5 -> threshold 4: only the dominant entry (cum 3 < 4).
    EXPECT_FALSE(isInTopZ(h, 20, 0.5));
}

TEST(InstanceRules, IsInTopZBoundaryIsInclusive)
{
    InstanceHist h;  // 8 and 2: the 2 holds exactly 1 - 0.8 of the mass
    h.add(1, 8.f);
    h.add(2, 2.f);
    EXPECT_TRUE(isInTopZ(h, 2, 0.8));
    EXPECT_FALSE(isInTopZ(h, 2, 0.75));  // needs 2.5
}

// Weights whose float sum rounds up: the entries hold exactly 1 - theta_b of the
// exact total (c = (a + b) / 4 exactly), so each is in the top set. With the
// total summed in float (as h.sum()), three of these cases fell out.
TEST(InstanceRules, IsInTopZHoldsAnEntryOfExactlyOneMinusThetaBWhateverTheFloatSum)
{
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> U(1.f, 50.f);
    int exact_cases = 0, float_sum_rounded_up = 0;
    for (int k = 0; k < 200000 && float_sum_rounded_up < 3; ++k)
    {
        float a = U(rng), b = U(rng);
        if (a < b) std::swap(a, b);
        const float c = float((double(a) + double(b)) / 4.0);
        if (double(c) * 4.0 != double(a) + double(b) || !(c < b)) continue;
        InstanceHist h;
        h.add(1, a);
        h.add(2, b);
        h.add(3, c);
        // The weights as stored (quantised ones round): the case holds only if they keep the tie.
        const auto stored = [&](uint32_t id) {
            const int i = h.indexOf(id);
            return i < 0 ? -1.0 : double(h.weight(i));
        };
        const double sa = stored(1), sb = stored(2), sc = stored(3);
        if (sc * 4.0 != sa + sb) continue;
        ++exact_cases;
        if (double(h.sum()) > sa + sb + sc) ++float_sum_rounded_up;
        EXPECT_TRUE(isInTopZ(h, 3, 0.8)) << a << " " << b << " " << c;
    }
    if (!kQuantisedHistograms)  // quantised weights hold few such ties: no rounding case to find
    {
        EXPECT_GE(float_sum_rounded_up, 3) << "no case where the float sum rounds up (of " << exact_cases << ")";
    }
}

TEST(InstanceRules, IsInTopZWithThetaBZeroHoldsTheStrongestEntry)
{
    InstanceHist h;  // float sum 10, the double sum of the entries 9.99999988
    h.add(1, 5.f);
    h.add(2, 3.1f);
    h.add(3, 1.9f);
    EXPECT_TRUE(isInTopZ(h, 1, 0.0));
    EXPECT_FALSE(isInTopZ(h, 3, 0.0));  // 1.9 of 10: only the strongest holds all of it
}

// A stuff share of exactly theta_st (wall + floor = 9 chair exactly) is no thing,
// also where the float sums rounded it to just below 0.9.
TEST(InstanceRules, IsThingAtAStuffShareOfExactlyThetaStWhateverTheFloatSums)
{
    const ClassSet classes = ClassSet::nyuv2_40();
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> U(1.f, 50.f);
    int exact_cases = 0, float_share_below = 0;
    for (int k = 0; k < 400000 && float_share_below < 3; ++k)
    {
        const float wall = U(rng), floor = U(rng);
        const float chair = float((double(wall) + double(floor)) / 9.0);
        if (double(chair) * 9.0 != double(wall) + double(floor)) continue;
        LabelRecord r;
        r.semantic.add(1, wall);
        r.semantic.add(2, floor);
        r.semantic.add(5, chair);
        const auto stored = [&](uint8_t id) {
            const int i = r.semantic.indexOf(id);
            return i < 0 ? -1.0 : double(r.semantic.weight(i));
        };
        if (stored(5) * 9.0 != stored(1) + stored(2)) continue;  // quantised weights may break the tie
        ++exact_cases;
        if (double(stuffMass(r, classes)) / double(r.semantic.sum()) < 0.9) ++float_share_below;
        EXPECT_FALSE(isThing(r, classes, 0.9)) << wall << " " << floor << " " << chair;
    }
    if (!kQuantisedHistograms)
    {
        EXPECT_GE(float_share_below, 3) << "no case where the float share falls below 0.9 (of " << exact_cases << ")";
    }
}

TEST(InstanceRules, IsThingUsesTheStuffShare)
{
    const ClassSet classes = ClassSet::nyuv2_40();
    LabelRecord r;
    r.semantic.add(1, 9.f);  // wall
    r.semantic.add(5, 1.f);  // chair
    EXPECT_FLOAT_EQ(stuffMass(r, classes), 9.f);
    EXPECT_FALSE(isThing(r, classes, 0.9));  // stuff share 0.9 is not < 0.9
    r.semantic.add(5, 0.25f);                // share 9/10.25 = 0.878
    EXPECT_TRUE(isThing(r, classes, 0.9));
    EXPECT_FALSE(isThing(LabelRecord{}, classes, 0.9));  // no semantic mass
}

TEST(InstanceRules, PThingFlipsAtThetaO)
{
    LabelRecord r;
    r.semantic.add(5, 10.f);
    r.n_l = 100;
    InstanceRecord z;
    z.hist.add(1, 8.f);
    z.n_z = 25;
    const ClassSet classes = ClassSet::nyuv2_40();
    EXPECT_TRUE(isPanopticThing(r, z, classes, 0.9, 0.25));
    z.n_z = 24;
    EXPECT_FALSE(isPanopticThing(r, z, classes, 0.9, 0.25));
}

TEST(InstanceRules, MatchThresholds)
{
    // J just above theta_m matches; exactly theta_m is the ambiguous band.
    EXPECT_EQ(classifyMatch(0.2 + 1e-9, 0.2, 0.1), MatchKind::Matched);
    EXPECT_EQ(classifyMatch(0.2, 0.2, 0.1), MatchKind::Ambiguous);
    EXPECT_EQ(classifyMatch(0.15, 0.2, 0.1), MatchKind::Ambiguous);
    EXPECT_EQ(classifyMatch(0.1 + 1e-9, 0.2, 0.1), MatchKind::Ambiguous);
    // J at or just below theta_n gets a new id.
    EXPECT_EQ(classifyMatch(0.1, 0.2, 0.1), MatchKind::New);
    EXPECT_EQ(classifyMatch(0.1 - 1e-9, 0.2, 0.1), MatchKind::New);
    EXPECT_EQ(classifyMatch(0.0, 0.2, 0.1), MatchKind::New);
}

TEST(InstanceRules, IntersectionOverUnionFromPixelCounts)
{
    EXPECT_DOUBLE_EQ(intersectionOverUnion(21, 50, 71), 0.21);  // union 100
    EXPECT_DOUBLE_EQ(intersectionOverUnion(10, 50, 60), 0.1);
    EXPECT_DOUBLE_EQ(intersectionOverUnion(0, 0, 0), 0.0);
    EXPECT_DOUBLE_EQ(intersectionOverUnion(30, 30, 30), 1.0);
}
