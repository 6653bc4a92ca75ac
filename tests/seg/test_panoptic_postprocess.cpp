// PanopticPostprocessor on hand-made tensors: every expected class, score, centre and instance
// below is computed by hand from the tensor values.
#include <gtest/gtest.h>
#include <pndt/panoptic_merge.h>
#include <pndt/seg/panoptic_postprocess.h>

#include <cmath>
#include <random>

using namespace pndt;
using namespace pndt::seg;

namespace
{
const ClassSet& nyu()
{
    static const ClassSet c = ClassSet::nyuv2_40();
    return c;
}
constexpr uint16_t kWall = 1, kChair = 5, kSofa = 6, kTable = 7;

/// Planar tensors of a W x H output with the given channel count, all zero.
struct Tensors
{
    int W, H, C;
    std::vector<float> semantic, center, offset;
    Tensors(int w, int h, int c) : W(w), H(h), C(c), semantic(size_t(w * h * c)), center(size_t(w * h)), offset(size_t(2 * w * h)) {}
    float& logit(int c, int y, int x) { return semantic[size_t(c * W * H + y * W + x)]; }
    float& heat(int y, int x) { return center[size_t(y * W + x)]; }
    float& dy(int y, int x) { return offset[size_t(y * W + x)]; }
    float& dx(int y, int x) { return offset[size_t(W * H + y * W + x)]; }
    PanopticTensors view(bool with_instances = true) const
    {
        PanopticTensors t;
        t.width = W;
        t.height = H;
        t.classes = C;
        t.semantic = semantic.data();
        if (with_instances)
        {
            t.center = center.data();
            t.offset = offset.data();
        }
        return t;
    }
};
}  // namespace

TEST(PanopticPostprocess, SoftmaxGivesTheWinningClassAndItsProbability)
{
    // Channels [void, wall, chair]; pixel 0 logits (0, 2, 1), pixel 1 (0, 0, 3).
    Tensors t(2, 1, 3);
    t.logit(1, 0, 0) = 2;
    t.logit(2, 0, 0) = 1;
    t.logit(2, 0, 1) = 3;
    PostprocessOptions o;
    PanopticPostprocessor p(nyu(), {0, kWall, kChair}, o);
    PanopticFrame out;
    p.run(t.view(false), out);
    EXPECT_EQ(out.semantic.at(0, 0), kWall);
    EXPECT_EQ(out.semantic.at(0, 1), kChair);
    // e^2 / (1 + e^2 + e^1) and e^3 / (1 + 1 + e^3)
    EXPECT_NEAR(out.semantic_score.at(0, 0), std::exp(2.) / (1 + std::exp(2.) + std::exp(1.)), 2e-6);
    EXPECT_NEAR(out.semantic_score.at(0, 1), std::exp(3.) / (2 + std::exp(3.)), 2e-6);
    EXPECT_TRUE(out.instance.empty()) << "semantic-only tensors give no instance image";
    EXPECT_TRUE(out.panoptic_score.empty());
}

TEST(PanopticPostprocess, ProbabilitiesAreTakenAsTheyAreWithoutSoftmax)
{
    Tensors t(1, 1, 2);
    t.logit(0, 0, 0) = 0.3f;
    t.logit(1, 0, 0) = 0.7f;
    PostprocessOptions o;
    o.semantic_is_logit = false;
    PanopticPostprocessor p(nyu(), {0, kWall}, o);
    PanopticFrame out;
    p.run(t.view(false), out);
    EXPECT_EQ(out.semantic.at(0, 0), kWall);
    EXPECT_FLOAT_EQ(out.semantic_score.at(0, 0), 0.7f);
}

TEST(PanopticPostprocess, LargeLogitsDoNotOverflow)
{
    Tensors t(1, 1, 2);
    t.logit(0, 0, 0) = 1000.f;
    t.logit(1, 0, 0) = 999.f;
    PanopticPostprocessor p(nyu(), {0, kWall}, {});
    PanopticFrame out;
    p.run(t.view(false), out);
    EXPECT_EQ(out.semantic.at(0, 0), 0);
    EXPECT_NEAR(out.semantic_score.at(0, 0), 1 / (1 + std::exp(-1.)), 2e-6);
}

TEST(PanopticPostprocess, CentresAreWindowMaximaAboveTheThresholdLimitedToTopK)
{
    // 9 x 1 heatmap, kernel 3: peaks at x=1 (0.8), x=2 (0.6, beside the larger 0.8: suppressed),
    // x=5 (0.5), x=7 (0.09, below the 0.1 threshold).
    Tensors t(9, 1, 2);
    const float heat[9] = {0.1f, 0.8f, 0.6f, 0.f, 0.2f, 0.5f, 0.f, 0.09f, 0.f};
    for (int x = 0; x < 9; ++x) t.heat(0, x) = heat[x];
    PostprocessOptions o;
    o.nms_kernel = 3;
    o.center_threshold = 0.1f;
    {
        PanopticPostprocessor p(nyu(), {0, kChair}, o);
        PanopticFrame out;
        p.run(t.view(), out);
        ASSERT_EQ(p.centers().size(), 2u);
        EXPECT_EQ(p.centers()[0].x, 1);
        EXPECT_FLOAT_EQ(p.centers()[0].score, 0.8f);
        EXPECT_EQ(p.centers()[1].x, 5);
    }
    o.top_k = 1;
    PanopticPostprocessor p(nyu(), {0, kChair}, o);
    PanopticFrame out;
    p.run(t.view(), out);
    ASSERT_EQ(p.centers().size(), 1u);
    EXPECT_EQ(p.centers()[0].x, 1);
}

TEST(PanopticPostprocess, CentreLogitsGoThroughASigmoid)
{
    Tensors t(1, 1, 2);
    t.logit(1, 0, 0) = 1;  // chair
    t.heat(0, 0) = 0.f;    // sigmoid(0) = 0.5
    PostprocessOptions o;
    o.center_is_logit = true;
    o.nms_kernel = 1;
    PanopticPostprocessor p(nyu(), {0, kChair}, o);
    PanopticFrame out;
    p.run(t.view(), out);
    ASSERT_EQ(p.centers().size(), 1u);
    EXPECT_FLOAT_EQ(p.centers()[0].score, 0.5f);
    EXPECT_EQ(out.instance.at(0, 0), 1u);
    EXPECT_NEAR(out.panoptic_score.at(0, 0), 0.5 * (std::exp(1.) / (1 + std::exp(1.))), 2e-6);
}

TEST(PanopticPostprocess, ThingPixelsJoinTheCentreTheirOffsetPointsTo)
{
    // 6 x 1 row: x=0 wall (stuff), x=1..5 chair. Centres at x=1 (0.9) and x=5 (0.7), kernel 3.
    // Offsets (xy order, scale 2): pixel 3 points +1 (to 3+2=5), pixel 2 points -0.5 (to 1),
    // pixel 4 has none (stays at 4: nearest centre 5).
    Tensors t(6, 1, 3);
    t.logit(1, 0, 0) = 5;
    for (int x = 1; x < 6; ++x) t.logit(2, 0, x) = 5;
    t.heat(0, 1) = 0.9f;
    t.heat(0, 5) = 0.7f;
    PostprocessOptions o;
    o.nms_kernel = 3;
    o.offset_yx = false;  // channel 0 = dx: Tensors::dy() addresses channel 0
    o.offset_scale = 2.f;
    t.dy(0, 3) = 1.f;
    t.dy(0, 2) = -0.5f;
    PanopticPostprocessor p(nyu(), {0, kWall, kChair}, o);
    PanopticFrame out;
    p.run(t.view(), out);
    const uint32_t expected[6] = {0, 1, 1, 2, 2, 2};
    for (int x = 0; x < 6; ++x) EXPECT_EQ(out.instance.at(0, x), expected[x]) << "pixel " << x;
    const float sl_chair = float(std::exp(5.) / (2 + std::exp(5.)));
    EXPECT_NEAR(out.panoptic_score.at(0, 2), sl_chair * 0.9f, 2e-6);
    EXPECT_NEAR(out.panoptic_score.at(0, 4), sl_chair * 0.7f, 2e-6);
    EXPECT_EQ(out.panoptic_score.at(0, 0), 0.f) << "stuff has no panoptic score";
}

TEST(PanopticPostprocess, AnInstanceTakesTheMajorityThingClassOfItsPixels)
{
    // One centre; pixels: 3 chair, 2 sofa, 1 table, 1 wall. All things join instance 1 and become
    // chair (Eq. 1); the wall pixel stays wall with instance 0; S^L stays each pixel's own.
    Tensors t(7, 1, 5);
    const int cls[7] = {2, 2, 2, 3, 3, 4, 1};  // channels: 0 void, 1 wall, 2 chair, 3 sofa, 4 table
    for (int x = 0; x < 7; ++x) t.logit(cls[x], 0, x) = 3;
    t.heat(0, 0) = 0.6f;
    PostprocessOptions o;
    o.nms_kernel = 3;
    PanopticPostprocessor p(nyu(), {0, kWall, kChair, kSofa, kTable}, o);
    PanopticFrame out;
    p.run(t.view(), out);
    for (int x = 0; x < 6; ++x)
    {
        EXPECT_EQ(out.semantic.at(0, x), kChair) << x;
        EXPECT_EQ(out.instance.at(0, x), 1u) << x;
    }
    EXPECT_EQ(out.semantic.at(0, 6), kWall);
    EXPECT_EQ(out.instance.at(0, 6), 0u);
}

TEST(PanopticPostprocess, AMajorityTieGoesToTheSmallerClassId)
{
    Tensors t(2, 1, 3);
    t.logit(2, 0, 0) = 3;  // table (7)
    t.logit(1, 0, 1) = 3;  // chair (5)
    t.heat(0, 0) = 0.5f;
    PostprocessOptions o;
    o.nms_kernel = 3;
    PanopticPostprocessor p(nyu(), {0, kChair, kTable}, o);
    PanopticFrame out;
    p.run(t.view(), out);
    EXPECT_EQ(out.semantic.at(0, 0), kChair);
    EXPECT_EQ(out.semantic.at(0, 1), kChair);
}

TEST(PanopticPostprocess, NoCentreLeavesThingsWithoutInstance)
{
    Tensors t(2, 1, 2);
    t.logit(1, 0, 0) = 2;
    t.logit(1, 0, 1) = 2;
    PanopticPostprocessor p(nyu(), {0, kChair}, {});
    PanopticFrame out;
    p.run(t.view(), out);
    EXPECT_TRUE(p.centers().empty());
    EXPECT_EQ(out.instance.at(0, 0), 0u);
    EXPECT_EQ(out.semantic.at(0, 0), kChair);
    EXPECT_EQ(out.panoptic_score.at(0, 1), 0.f);
}

TEST(PanopticPostprocess, MergeEqualsTheCorePanopticMergeOnRandomTensors)
{
    // Our in-place Eq. 1 must agree with core's panopticMerge applied to the same grouping.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-3.f, 3.f), h(0.f, 1.f), off(-6.f, 6.f);
    Tensors t(40, 30, 6);
    for (auto& v : t.semantic) v = u(rng);
    for (auto& v : t.center) v = h(rng) < 0.995f ? 0.f : h(rng);
    for (auto& v : t.offset) v = off(rng);
    PostprocessOptions o;
    o.nms_kernel = 5;
    const std::vector<uint16_t> map = {0, kWall, kChair, kSofa, kTable, 2 /*floor*/};
    PanopticPostprocessor p(nyu(), map, o);
    PanopticFrame out;
    p.run(t.view(), out);
    ASSERT_GE(p.centers().size(), 2u);

    // Rebuild the pre-merge images: argmax class + S^L, instance from out (things only), S^Z.
    Image<uint16_t> sem(40, 30);
    Image<float> sl(40, 30), sz(40, 30);
    Image<uint32_t> inst = out.instance;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x)
        {
            int best = 0;
            for (int c = 1; c < 6; ++c)
                if (t.logit(c, y, x) > t.logit(best, y, x)) best = c;
            double sum = 0;
            for (int c = 0; c < 6; ++c) sum += std::exp(double(t.logit(c, y, x) - t.logit(best, y, x)));
            sem.at(y, x) = map[size_t(best)];
            sl.at(y, x) = float(1 / sum);
            const uint32_t z = inst.at(y, x);
            sz.at(y, x) = z ? p.centers()[z - 1].score : 0.f;
            EXPECT_NEAR(out.semantic_score.at(y, x), sl.at(y, x), 2e-6);
        }
    Image<uint16_t> ms;
    Image<uint32_t> mi;
    Image<float> mp;
    panopticMerge(nyu(), sem, sl, inst, sz, ms, mi, mp);
    EXPECT_EQ(ms.data, out.semantic.data);
    EXPECT_EQ(mi.data, out.instance.data);
    for (size_t i = 0; i < mp.data.size(); ++i) ASSERT_NEAR(mp.data[i], out.panoptic_score.data[i], 2e-6) << i;
}

TEST(PanopticPostprocess, BadTensorsAreClearErrors)
{
    Tensors t(2, 2, 3);
    PanopticPostprocessor p(nyu(), {0, kWall}, {});
    PanopticFrame out;
    try
    {
        p.run(t.view(), out);
        FAIL() << "channel mismatch accepted";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("3 channels"), std::string::npos) << e.what();
    }
    Tensors n(2, 1, 2);
    n.logit(0, 0, 1) = std::nanf("");
    n.logit(1, 0, 1) = std::nanf("");
    EXPECT_THROW(p.run(n.view(false), out), InputError);
    PostprocessOptions even;
    even.nms_kernel = 4;
    EXPECT_THROW(PanopticPostprocessor(nyu(), {0}, even), InputError);
    EXPECT_THROW(PanopticPostprocessor(nyu(), {0, 200}, {}), InputError) << "class id outside the set";
}

TEST(ResizeLabels, DoublingRepeatsEachPixelTwiceEachWay)
{
    PanopticFrame small;
    small.semantic = Image<uint16_t>(2, 1);
    small.semantic.data = {3, 4};
    small.semantic_score = Image<float>(2, 1, 0.5f);
    small.instance = Image<uint32_t>(2, 1);
    small.instance.data = {0, 9};
    small.panoptic_score = Image<float>(2, 1);
    small.panoptic_score.data = {0.f, 0.25f};
    PanopticFrame big;
    resizeLabels(small, 4, 2, big);
    EXPECT_EQ(big.semantic.data, (std::vector<uint16_t>{3, 3, 4, 4, 3, 3, 4, 4}));
    EXPECT_EQ(big.instance.data, (std::vector<uint32_t>{0, 0, 9, 9, 0, 0, 9, 9}));
    EXPECT_EQ(big.panoptic_score.at(1, 3), 0.25f);
    EXPECT_EQ(big.semantic_score.at(1, 0), 0.5f);
}
