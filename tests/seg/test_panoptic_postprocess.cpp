// PanopticPostprocessor on hand-made tensors: every expected class, score, centre and instance
// below is computed by hand from the tensor values.
#include <gtest/gtest.h>
#include <pndt/panoptic_merge.h>
#include <pndt/seg/panoptic_postprocess.h>

#include <algorithm>
#include <cmath>
#include <limits>
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

TEST(ResizeLabels, EveryPixelTakesTheSourcePixelUnderItsCentre)
{
    // Up, down, odd ratios and a frame that held larger images: target (x, y) takes source
    // (floor((x + 0.5) W / width), floor((y + 0.5) H / height)), computed here in double.
    const int sizes[][4] = {{160, 120, 640, 480}, {7, 5, 13, 11}, {20, 10, 3, 4}, {3, 3, 640, 1}, {64, 48, 64, 48}};
    PanopticFrame big;
    big.semantic = Image<uint16_t>(1000, 1000, 9);
    for (const auto& sz : sizes)
    {
        const int W = sz[0], H = sz[1], width = sz[2], height = sz[3];
        PanopticFrame small;
        small.semantic = Image<uint16_t>(W, H);
        small.semantic_score = Image<float>(W, H);
        small.instance = Image<uint32_t>(W, H);
        small.panoptic_score = Image<float>(W, H);
        for (int i = 0; i < W * H; ++i)
        {
            small.semantic.data[size_t(i)] = uint16_t(i % 65000);
            small.semantic_score.data[size_t(i)] = float(i) * 0.5f;
            small.instance.data[size_t(i)] = uint32_t(i) + 70000;
            small.panoptic_score.data[size_t(i)] = float(i) * 0.25f;
        }
        resizeLabels(small, width, height, big);
        ASSERT_EQ(big.semantic.width, width);
        ASSERT_EQ(big.semantic.height, height);
        ASSERT_EQ(big.panoptic_score.size(), size_t(width * height));
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
            {
                const int sy = std::min(H - 1, int((y + 0.5) * H / height));
                const int sx = std::min(W - 1, int((x + 0.5) * W / width));
                const int i = sy * W + sx;
                ASSERT_EQ(big.semantic.at(y, x), uint16_t(i % 65000)) << W << "x" << H << " -> " << x << "," << y;
                ASSERT_EQ(big.semantic_score.at(y, x), float(i) * 0.5f);
                ASSERT_EQ(big.instance.at(y, x), uint32_t(i) + 70000);
                ASSERT_EQ(big.panoptic_score.at(y, x), float(i) * 0.25f);
            }
    }
    // Labels without instances give none; labels of mismatched sizes are an error, not a read
    // past the end.
    PanopticFrame semantic_only;
    semantic_only.semantic = Image<uint16_t>(2, 2, 1);
    semantic_only.semantic_score = Image<float>(2, 2, 0.5f);
    resizeLabels(semantic_only, 4, 4, big);
    EXPECT_TRUE(big.instance.empty());
    EXPECT_EQ(big.semantic.data, std::vector<uint16_t>(16, 1));
    semantic_only.semantic_score = Image<float>(1, 2, 0.5f);
    EXPECT_THROW(resizeLabels(semantic_only, 4, 4, big), InputError);
    EXPECT_THROW(resizeLabels(PanopticFrame{}, 4, 4, big), InputError);
}

// ---- The fast paths: skipped classes in S^L, the sparse NMS, the centre grid of the grouping. ----

namespace
{
/// S^L by the definition, in double.
double exactScore(Tensors& t, int y, int x)
{
    double mx = -1e300, sum = 0;
    for (int c = 0; c < t.C; ++c) mx = std::max(mx, double(t.logit(c, y, x)));
    for (int c = 0; c < t.C; ++c) sum += std::exp(double(t.logit(c, y, x)) - mx);
    return 1 / sum;
}
}  // namespace

TEST(PanopticPostprocessFast, AClassCloseToTheWinnerAtOnePixelIsNotSkipped)
{
    // 256 x 1 (four 64-pixel sub-blocks, 8-pixel vectors), channels [void, wall, chair]. Chair sits
    // 40 below everywhere (skipped), wall 30 below except at pixel 200, where it is only 5 below:
    // its e^-5 = 0.0067 must be in that pixel's sum. Pixel 7: chair wins by 1 over void.
    for (const int width : {256, 255})  // 255: the last block is not a whole number of vectors
    {
        Tensors t(width, 1, 3);
        for (int x = 0; x < width; ++x)
        {
            t.logit(1, 0, x) = -30.f;
            t.logit(2, 0, x) = -40.f;
        }
        t.logit(1, 0, 200) = -5.f;
        t.logit(2, 0, 7) = 1.f;
        PanopticPostprocessor p(nyu(), {0, kWall, kChair}, {});
        PanopticFrame out;
        p.run(t.view(false), out);
        for (int x = 0; x < width; ++x)
        {
            EXPECT_EQ(out.semantic.at(0, x), x == 7 ? kChair : 0) << x;
            EXPECT_NEAR(out.semantic_score.at(0, x), exactScore(t, 0, x), 2e-6) << x;
        }
        EXPECT_NEAR(out.semantic_score.at(0, 200), 1 / (1 + std::exp(-5.)), 2e-6);
        EXPECT_NEAR(out.semantic_score.at(0, 7), 1 / (1 + std::exp(-1.)), 2e-6);
    }
}

TEST(PanopticPostprocessFast, SkippedClassesStayWithinTheScoreTolerance)
{
    // 41 channels: a winner, a runner-up 2..14 below, the others 8..40 below: S^L within
    // score_tolerance (+ 3e-6 for the exp) of the definition, and within 3e-6 with tolerance 0.
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> runner(2.f, 14.f), other(8.f, 40.f), level(-5.f, 15.f);
    Tensors t(64, 8, 41);
    std::vector<uint16_t> map(41);
    for (int c = 0; c < 41; ++c) map[size_t(c)] = uint16_t(c);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 64; ++x)
        {
            const int win = (x / 16 + 3 * y) % 41, second = (win + 1) % 41;
            const float l = level(rng);
            for (int c = 0; c < 41; ++c)
                t.logit(c, y, x) = c == win ? l : c == second ? l - runner(rng) : l - other(rng);
        }
    for (const float tolerance : {1e-4f, 1e-3f, 0.f})
    {
        PostprocessOptions o;
        o.score_tolerance = tolerance;
        PanopticPostprocessor p(nyu(), map, o);
        PanopticFrame out;
        p.run(t.view(false), out);
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 64; ++x)
            {
                const double s = exactScore(t, y, x);
                EXPECT_EQ(out.semantic.at(y, x), (x / 16 + 3 * y) % 41);
                ASSERT_LE(std::abs(out.semantic_score.at(y, x) - s), (tolerance + 3e-6) * s) << tolerance;
            }
    }
}

TEST(PanopticPostprocessFast, NonFiniteLogitsAreFoundInEveryChannel)
{
    // A NaN in a channel that is nobody's winner still makes the frame an error (as the
    // definition's sum would be NaN); −inf is a logit of probability 0.
    Tensors t(16, 1, 3);
    for (int x = 0; x < 16; ++x) t.logit(1, 0, x) = 4.f;
    PanopticPostprocessor p(nyu(), {0, kWall, kChair}, {});
    PanopticFrame out;
    t.logit(2, 0, 9) = std::nanf("");
    EXPECT_THROW(p.run(t.view(false), out), InputError);
    t.logit(2, 0, 9) = -std::numeric_limits<float>::infinity();
    p.run(t.view(false), out);
    EXPECT_EQ(out.semantic.at(0, 9), kWall);
    EXPECT_NEAR(out.semantic_score.at(0, 9), 1 / (1 + std::exp(-4.)), 2e-6);
}

namespace
{
PostprocessOptions withKernel(int nms_kernel, float offset_scale = 1.f)
{
    PostprocessOptions o;
    o.nms_kernel = nms_kernel;
    o.offset_scale = offset_scale;
    return o;
}

/// Centres by the definition: above the threshold and ≥ every value of the window (image only).
std::vector<InstanceCenter> referenceCentres(const Tensors& t, const PostprocessOptions& o)
{
    std::vector<InstanceCenter> c;
    const int r = o.nms_kernel / 2;
    for (int y = 0; y < t.H; ++y)
        for (int x = 0; x < t.W; ++x)
        {
            const float v = t.center[size_t(y * t.W + x)];
            bool peak = v > o.center_threshold;
            for (int yy = std::max(0, y - r); peak && yy <= std::min(t.H - 1, y + r); ++yy)
                for (int xx = std::max(0, x - r); peak && xx <= std::min(t.W - 1, x + r); ++xx)
                    peak = v >= t.center[size_t(yy * t.W + xx)];
            if (peak) c.push_back({x, y, std::min(v, 1.f)});
        }
    std::stable_sort(c.begin(), c.end(), [](const InstanceCenter& a, const InstanceCenter& b) { return a.score > b.score; });
    if (int(c.size()) > o.top_k) c.resize(size_t(o.top_k));
    return c;
}
}  // namespace

TEST(PanopticPostprocessFast, CentresEqualTheDefinitionOnSmoothAndOnNoisyHeatmaps)
{
    // Smooth: Gaussian peaks (the sparse search), with a plateau of two equal maxima.
    // Noisy: iid values above the threshold everywhere (too many local maxima: the max filter).
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (const bool noisy : {false, true})
    {
        Tensors t(96, 64, 2);
        if (noisy)
            for (auto& v : t.center) v = 0.2f + 0.8f * u(rng);
        else
        {
            for (int k = 0; k < 12; ++k)
            {
                const float cx = 96 * u(rng), cy = 64 * u(rng), peak = 0.3f + 0.7f * u(rng);
                for (int y = 0; y < 64; ++y)
                    for (int x = 0; x < 96; ++x)
                    {
                        float& v = t.heat(y, x);
                        v = std::max(v, peak * std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / 50.f));
                    }
            }
            t.heat(30, 10) = t.heat(30, 12) = 1.f;  // a plateau: both are centres
        }
        const PostprocessOptions o = withKernel(7);
        PanopticPostprocessor p(nyu(), {0, kChair}, o);
        PanopticFrame out;
        p.run(t.view(), out);
        const auto ref = referenceCentres(t, o);
        ASSERT_EQ(p.centers().size(), ref.size()) << (noisy ? "noisy" : "smooth");
        ASSERT_GE(ref.size(), noisy ? 20u : 5u);
        for (size_t k = 0; k < ref.size(); ++k)
        {
            EXPECT_EQ(p.centers()[k].x, ref[k].x) << k;
            EXPECT_EQ(p.centers()[k].y, ref[k].y) << k;
            EXPECT_EQ(p.centers()[k].score, ref[k].score) << k;
        }
    }
}

TEST(PanopticPostprocessFast, GroupingEqualsTheNearestCentreForEveryVote)
{
    // 40 centres on a 160 x 120 output, thing pixels everywhere, offsets that send votes all over
    // (outside the image too, a NaN): each pixel's instance is its vote's nearest centre by a
    // brute-force search (ties: the earlier centre), whatever the grid cell it falls into.
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.f, 1.f), off(-60.f, 60.f);
    Tensors t(160, 120, 2);
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x) t.logit(1, y, x) = 3.f;  // chair
    for (int k = 0; k < 40; ++k) t.heat(int(120 * u(rng)), int(160 * u(rng))) = 0.2f + 0.8f * u(rng);
    for (auto& v : t.offset) v = off(rng);
    t.dy(5, 5) = std::nanf("");
    t.dx(6, 6) = 500.f;
    const PostprocessOptions o = withKernel(3, 0.75f);
    PanopticPostprocessor p(nyu(), {0, kChair}, o);
    PanopticFrame out;
    p.run(t.view(), out);
    const auto& cs = p.centers();
    ASSERT_GE(cs.size(), 30u);
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x)
        {
            const float vx = float(x) + o.offset_scale * t.dx(y, x), vy = float(y) + o.offset_scale * t.dy(y, x);
            float best = std::numeric_limits<float>::infinity();
            uint32_t id = 0;
            for (size_t k = 0; k < cs.size(); ++k)
            {
                const float ex = vx - float(cs[k].x), ey = vy - float(cs[k].y);
                const float d = ex * ex + ey * ey;
                if (d < best)
                {
                    best = d;
                    id = uint32_t(k + 1);
                }
            }
            ASSERT_EQ(out.instance.at(y, x), id) << x << "," << y;
        }
    EXPECT_EQ(out.instance.at(5, 5), 0u) << "a NaN vote joins no instance";
}

TEST(PanopticPostprocessFast, EveryKernelGivesTheSameOutputs)
{
    // A network-like output (regions with clear winners, close rivals at their borders, thing
    // regions with centre peaks and offsets towards them, noise), at a size of whole 64-pixel
    // sub-blocks and at one with a ragged last block. The widest kernel (AVX-512 where the CPU
    // has it) and the AVX2 one agree bit for bit; the scalar one in labels and instances, and in
    // scores to the polynomial exp's rounding.
    for (const auto& [W, H] : {std::pair{128, 96}, std::pair{100, 37}})
    {
        std::mt19937 rng(11);
        std::normal_distribution<float> noise(0.f, 0.5f);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        const int C = 41;
        Tensors t(W, H, C);
        const int R = 16;  // 16 x 16 pixel regions
        std::vector<int> winner;
        for (int r = 0; r < ((W + R - 1) / R) * ((H + R - 1) / R); ++r) winner.push_back(int(u(rng) * C) % C);
        // Many centres and votes scattered around them: the nearest centre changes within a pixel
        // or two at many votes, so a vote's position must be exact.
        std::vector<std::pair<int, int>> peaks;
        for (int k = 0; k < 14; ++k) peaks.emplace_back(int(u(rng) * float(W - 1)), int(u(rng) * float(H - 1)));
        std::uniform_real_distribution<float> scatter(-12.f, 12.f);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
            {
                const int w = winner[size_t((y / R) * ((W + R - 1) / R) + x / R)];
                for (int c = 0; c < C; ++c) t.logit(c, y, x) = -8.f + 3.f * noise(rng);
                t.logit(w, y, x) = 6.f + noise(rng);
                if (x % R == 0) t.logit((w + 1) % C, y, x) = 5.5f;  // a close rival at region borders
                float best = 0;
                for (const auto& [px, py] : peaks)
                {
                    const float d2 = float((x - px) * (x - px) + (y - py) * (y - py));
                    best = std::max(best, std::exp(-d2 / 50.f));
                }
                t.heat(y, x) = best;
                const auto& [px, py] = *std::min_element(peaks.begin(), peaks.end(), [&](auto a, auto b) {
                    return (x - a.first) * (x - a.first) + (y - a.second) * (y - a.second) <
                           (x - b.first) * (x - b.first) + (y - b.second) * (y - b.second);
                });
                t.dx(y, x) = float(px - x) + scatter(rng);
                t.dy(y, x) = float(py - y) + scatter(rng);
            }
        std::vector<uint16_t> map(C);
        for (int c = 0; c < C; ++c) map[size_t(c)] = uint16_t(c);  // NYUv2-40 + void: things and stuff
        auto runWith = [&](PostprocessOptions::Kernel k) {
            PostprocessOptions o;
            o.nms_kernel = 5;
            o.kernel = k;
            PanopticPostprocessor p(nyu(), map, o);
            PanopticFrame out;
            p.run(t.view(), out);
            p.run(t.view(), out);  // a second frame into the same images
            return out;
        };
        const PanopticFrame best = runWith(PostprocessOptions::Kernel::Best);
        const PanopticFrame avx2 = runWith(PostprocessOptions::Kernel::Avx2);
        const PanopticFrame scalar = runWith(PostprocessOptions::Kernel::Scalar);
        size_t thing_pixels = 0;
        for (uint32_t z : best.instance.data) thing_pixels += z != 0;
        EXPECT_GT(thing_pixels, size_t(W * H / 20)) << W << "x" << H;  // the grouping was exercised
        EXPECT_EQ(best.semantic.data, avx2.semantic.data);
        EXPECT_EQ(best.instance.data, avx2.instance.data);
        EXPECT_EQ(best.semantic_score.data, avx2.semantic_score.data);
        EXPECT_EQ(best.panoptic_score.data, avx2.panoptic_score.data);
        EXPECT_EQ(best.semantic.data, scalar.semantic.data);
        EXPECT_EQ(best.instance.data, scalar.instance.data);
        for (size_t i = 0; i < best.semantic_score.data.size(); ++i)
        {
            ASSERT_NEAR(best.semantic_score.data[i], scalar.semantic_score.data[i], 3e-6f * best.semantic_score.data[i]);
            ASSERT_NEAR(best.panoptic_score.data[i], scalar.panoptic_score.data[i], 3e-6f * best.semantic_score.data[i]);
        }
    }
}
