// The design §5 carriers pndt-map and pndt-live read every frame: range scans to depth and the
// two "id + score" float images to labels, and back. Expected values by the definitions
// (id = floor(v), score = v - id; depth = range / sqrt(1 + x^2 + y^2)), for every id range.
#include <gtest/gtest.h>
#include <pndt/mrpt/observation_frame.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "observation_fixtures.h"

using namespace pndt;

namespace
{
/// A label image whose pixels are `values`, repeated in raster order.
mrpt::obs::CObservationImage::Ptr imageOf(const std::string& suffix, const std::vector<float>& values)
{
    auto o = fixtures::labelImage(0, suffix, 0.f, 0.f);
    for (int r = 0; r < fixtures::kH; ++r)
    {
        float* row = o->image.ptrLine<float>(r);
        for (int c = 0; c < fixtures::kW; ++c) row[c] = values[size_t(r * fixtures::kW + c) % values.size()];
    }
    return o;
}

PanopticFrame wallFrame()
{
    PanopticFrame f;
    depthFrameFrom(*fixtures::wallScan(0), f);
    return f;
}

std::string errorOf(const mrpt::obs::CObservationImage& sem, const mrpt::obs::CObservationImage& inst)
{
    PanopticFrame f = wallFrame();
    try
    {
        attachPanopticLabels(sem, inst, f);
    }
    catch (const InputError& e)
    {
        // No half-decoded labels are left behind (the semantic image may have decoded fine).
        EXPECT_FALSE(f.hasLabels() || f.hasInstances() || !f.semantic_score.empty() || !f.panoptic_score.empty());
        return e.what();
    }
    return "no error";
}
}  // namespace

TEST(LabelCarrier, DecodesFloorAndFractionInEveryIdRange)
{
    // Both sides of 2^16 (instances only), 2^24 (floats are integers from there) and 2^31
    // (the decode's int32 step), the largest float below 2^32, scores near 0 and 1.
    const std::vector<float> instance_values = {0.f,         0.999f,       7.25f,         65535.5f,
                                                65536.f,     70000.125f,   16777215.5f,   16777216.f,
                                                2147483520.f, 2147483648.f, 3000000000.f, 4294967040.f,
                                                1.f / 3.f,   12345.678f,   0.0001f};
    const std::vector<float> semantic_values = {0.f, 1.5f, 40.999f, 65535.5f, 3.0001f, 0.25f, 17.f};
    PanopticFrame f = wallFrame();
    attachPanopticLabels(*imageOf("_PANOPTIC_SEMANTIC", semantic_values),
                         *imageOf("_PANOPTIC_INSTANCE", instance_values), f);
    ASSERT_EQ(f.semantic.size(), size_t(fixtures::kW * fixtures::kH));
    for (size_t i = 0; i < f.semantic.size(); ++i)
    {
        const float s = semantic_values[i % semantic_values.size()], z = instance_values[i % instance_values.size()];
        ASSERT_EQ(f.semantic.data[i], uint16_t(std::floor(s))) << s;
        ASSERT_EQ(f.semantic_score.data[i], s - std::floor(s)) << s;
        ASSERT_EQ(f.instance.data[i], uint32_t(std::floor(z))) << z;
        ASSERT_EQ(f.panoptic_score.data[i], z - std::floor(z)) << z;
    }
}

TEST(LabelCarrier, EncodedLabelsDecodeToThemselves)
{
    PanopticFrame f = wallFrame();
    const size_t n = f.depth.size();
    f.semantic.resize(fixtures::kW, fixtures::kH);
    f.semantic_score.resize(fixtures::kW, fixtures::kH);
    f.instance.resize(fixtures::kW, fixtures::kH);
    f.panoptic_score.resize(fixtures::kW, fixtures::kH);
    for (size_t i = 0; i < n; ++i)
    {
        f.semantic.data[i] = uint16_t(i % 41);
        f.semantic_score.data[i] = i % 7 == 0 ? 1.5f : 0.125f * float(i % 8);  // 1.5 is clamped to 0.999
        f.instance.data[i] = i % 3 ? 0 : uint32_t(65536 + i);                // > 16 bits after a hand-over
        f.panoptic_score.data[i] = i % 5 == 0 ? -0.5f : 0.0625f * float(i % 16);  // clamped to 0
    }
    mrpt::obs::CObservationImage sem, inst;
    labelImagesFrom(f, "RGBD", fixtures::stamp(0), sem, inst);
    EXPECT_EQ(sem.sensorLabel, "RGBD_PANOPTIC_SEMANTIC");
    EXPECT_EQ(inst.sensorLabel, "RGBD_PANOPTIC_INSTANCE");
    PanopticFrame g = wallFrame();
    attachPanopticLabels(sem, inst, g);
    EXPECT_EQ(g.semantic.data, f.semantic.data);
    EXPECT_EQ(g.instance.data, f.instance.data);
    for (size_t i = 0; i < n; ++i)
    {
        // float(id) + score rounds the score to the id's float spacing, kept below id + 1:
        // compare as encoded.
        const auto encoded = [](uint32_t id, float score) {
            return std::min(float(id) + std::clamp(score, 0.f, 0.999f), std::nextafter(float(id) + 1.f, 0.f));
        };
        const float s = encoded(f.semantic.data[i], f.semantic_score.data[i]);
        const float z = encoded(f.instance.data[i], f.panoptic_score.data[i]);
        ASSERT_EQ(g.semantic_score.data[i], s - std::floor(s)) << i;
        ASSERT_EQ(g.panoptic_score.data[i], z - std::floor(z)) << i;
    }
    // Without instances: an instance image of zeros, no instance and score 0 everywhere.
    f.instance = {};
    f.panoptic_score = {};
    labelImagesFrom(f, "RGBD", fixtures::stamp(0), sem, inst);
    attachPanopticLabels(sem, inst, g);
    EXPECT_EQ(g.instance.data, std::vector<uint32_t>(n, 0));
    EXPECT_EQ(g.panoptic_score.data, std::vector<float>(n, 0.f));
}

// From 2^15 on the float spacing exceeds 0.002: id + 0.999 rounded to id + 1, so a pixel of
// instance 32768 with score 0.999 came back as instance 32769 (4194304 + 0.9 as 4194305).
TEST(LabelCarrier, LargeIdsComeBackExactAndIdsBeyond2To24AreRefused)
{
    PanopticFrame f = wallFrame();
    const std::vector<uint32_t> ids = {32768, 40000, 65535, 65536, 1000000, 4194304, 16777215};
    const std::vector<float> scores = {0.999f, 0.9f, 0.5f, 0.1f};
    f.semantic.resize(fixtures::kW, fixtures::kH, 5);
    f.semantic_score.resize(fixtures::kW, fixtures::kH, 0.999f);
    f.instance.resize(fixtures::kW, fixtures::kH);
    f.panoptic_score.resize(fixtures::kW, fixtures::kH);
    for (size_t i = 0; i < f.instance.size(); ++i)
    {
        f.instance.data[i] = ids[i % ids.size()];
        f.panoptic_score.data[i] = scores[i % scores.size()];
    }
    mrpt::obs::CObservationImage sem, inst;
    labelImagesFrom(f, "RGBD", fixtures::stamp(0), sem, inst);
    PanopticFrame g = wallFrame();
    attachPanopticLabels(sem, inst, g);
    EXPECT_EQ(g.instance.data, f.instance.data);
    for (size_t i = 0; i < f.instance.size(); ++i)
    {
        // The score as precise as the id's float spacing allows (0.5 at 2^22).
        const float spacing = std::nextafter(float(f.instance.data[i]) + 1.f, 2e9f) - (float(f.instance.data[i]) + 1.f);
        ASSERT_LE(std::abs(g.panoptic_score.data[i] - f.panoptic_score.data[i]), std::max(spacing, 0.002f))
            << f.instance.data[i] << " " << f.panoptic_score.data[i];
    }
    f.instance.data[7] = 16777216;
    try
    {
        labelImagesFrom(f, "RGBD", fixtures::stamp(0), sem, inst);
        ADD_FAILURE() << "id 2^24 encoded";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("instance id 16777216 at pixel (row 0, col 7) does not fit"),
                  std::string::npos)
            << e.what();
    }
}

TEST(LabelCarrier, ErrorsNameTheFirstBadPixelInTheOrderTheyAreChecked)
{
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const auto good_sem = fixtures::semanticImage(0);
    const auto good_inst = fixtures::labelImage(0, "_PANOPTIC_INSTANCE", 0.f, 7.8f);
    auto bad = [&](const std::string& suffix, int row, int col, float v) {
        auto o = suffix == "_PANOPTIC_SEMANTIC" ? fixtures::semanticImage(0)
                                                : fixtures::labelImage(0, "_PANOPTIC_INSTANCE", 0.f, 7.8f);
        o->image.ptrLine<float>(row)[col] = v;
        return o;
    };
    for (const float v : {nan, inf, -0.5f, 4294967296.f})
    {
        const std::string e = errorOf(*bad("_PANOPTIC_SEMANTIC", 3, 17, v), *good_inst);
        EXPECT_NE(e.find("'RGBD_PANOPTIC_SEMANTIC'"), std::string::npos) << e;
        EXPECT_NE(e.find("invalid id+score value"), std::string::npos) << e;
        EXPECT_NE(e.find("row 3, col 17"), std::string::npos) << e;
        const std::string ei = errorOf(*good_sem, *bad("_PANOPTIC_INSTANCE", 20, 2, v));
        EXPECT_NE(ei.find("'RGBD_PANOPTIC_INSTANCE'"), std::string::npos) << ei;
        EXPECT_NE(ei.find("row 20, col 2"), std::string::npos) << ei;
    }
    // A class id beyond 16 bits is valid id+score but not a class: named with its id...
    const std::string wide = errorOf(*bad("_PANOPTIC_SEMANTIC", 1, 1, 70000.5f), *good_inst);
    EXPECT_NE(wide.find("class id 70000 does not fit 16 bits"), std::string::npos) << wide;
    // ...and reported after an invalid instance value, as it always was.
    const std::string both = errorOf(*bad("_PANOPTIC_SEMANTIC", 1, 1, 70000.5f), *bad("_PANOPTIC_INSTANCE", 5, 6, nan));
    EXPECT_NE(both.find("row 5, col 6"), std::string::npos) << both;
    // The first of two bad pixels in raster order.
    auto two = bad("_PANOPTIC_SEMANTIC", 9, 30, -1.f);
    two->image.ptrLine<float>(10)[0] = nan;
    const std::string first = errorOf(*two, *good_inst);
    EXPECT_NE(first.find("row 9, col 30"), std::string::npos) << first;
}

TEST(LabelCarrier, RayLengthRangesBecomeDepthAlongTheOpticalAxis)
{
    auto scan = fixtures::wallScan(0);
    scan->range_is_depth = false;
    for (int r = 0; r < fixtures::kH; ++r)
        for (int c = 0; c < fixtures::kW; ++c) scan->rangeImage(r, c) = uint16_t((r * 37 + c * 11) % 3 ? 1000 + r * 50 + c : 0);
    PanopticFrame f;
    depthFrameFrom(*scan, f);
    ASSERT_EQ(f.depth.width, fixtures::kW);
    ASSERT_EQ(f.depth.height, fixtures::kH);
    for (int r = 0; r < fixtures::kH; ++r)
        for (int c = 0; c < fixtures::kW; ++c)
        {
            const float range = float(scan->rangeImage(r, c)) * 0.001f;
            const double x = (c - 15.5) / 16.0, y = (r - 11.5) / 16.0;
            const float expected = range > 0 ? float(range / std::sqrt(1.0 + x * x + y * y)) : 0.f;
            ASSERT_EQ(f.depth.at(r, c), expected) << r << " " << c;
        }
    // Depth ranges are copied as they are, also into a frame that held a larger image before.
    PanopticFrame big;
    big.depth = Image<float>(100, 100, 7.f);
    depthFrameFrom(*fixtures::wallScan(0, 1.5f), big);
    EXPECT_EQ(big.depth.data, std::vector<float>(size_t(fixtures::kW * fixtures::kH), float(1500) * 0.001f));
}
