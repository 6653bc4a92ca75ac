// loadSegmenter + OpenCV DNN on tiny ONNX models (make_test_models.py) whose outputs are
// hand-computable: the whole front-end, preprocessing to label images, and its errors.
#include <gtest/gtest.h>
#include <pndt/seg/segmenter.h>

#include <cmath>
#include <fstream>

#include "seg_test_util.h"

using namespace pndt;
using namespace pndt::seg;

namespace
{
const std::string kModels = PNDT_SEG_TEST_MODELS;
constexpr int W = 16, H = 12;
constexpr uint16_t kWall = 1, kChair = 5, kTable = 7;

const ClassSet& nyu()
{
    static const ClassSet c = ClassSet::nyuv2_40();
    return c;
}

std::string description(const std::string& onnx, const std::string& kind, int w, int h,
                        const std::string& rgb_kind = "rgb")
{
    const std::string outputs = kind == "semantic" ? R"({"semantic": "semantic"})"
                                                   : R"({"semantic": "semantic", "center": "center", "offset": "offset"})";
    const std::string text = R"({"format": "pndt-segmentation-model/1", "name": "tiny", "onnx": ")" + kModels + "/" +
                             onnx + R"(", "kind": ")" + kind + R"(", "input_size": [)" + std::to_string(w) + ", " +
                             std::to_string(h) + R"(],
      "inputs": [{"name": "rgb", "kind": ")" + rgb_kind + R"(", "scale": 0.003921568627451},
                 {"name": "depth", "kind": "depth", "mean": [2], "std": [10]}],
      "outputs": )" + outputs + R"(,
      "classes": ["void", "wall", "chair", "table"],
      "postprocess": {"center_threshold": 0.1, "nms_kernel": 3, "top_k": 8, "offset_order": "yx", "offset_scale": 2}})";
    const auto dir = test::tempDir(onnx + kind + rgb_kind + std::to_string(w));
    return test::writeText(dir / "model.json", text);
}

/// Left half red (wall), right top green (chair), right bottom blue (table); depth 1 m except
/// three centre pixels whose normalised depth (d − 2) / 10 is the centre heatmap value.
struct Scene
{
    Image<RgbPixel> color{W, H};
    Image<float> depth{W, H, 1.f};
    CameraIntrinsics K{W, H, 20, 20, 7.5, 5.5};
    struct Centre { int x, y; float depth; };
    std::vector<Centre> centres{{10, 2, 9.f}, {14, 4, 8.f}, {12, 8, 7.f}};  // heat 0.7, 0.6, 0.5

    Scene()
    {
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
                color.at(y, x) = x < 8 ? RgbPixel{255, 0, 0} : y < 6 ? RgbPixel{0, 255, 0} : RgbPixel{0, 0, 255};
        for (const auto& c : centres) depth.at(c.y, c.x) = c.depth;
    }
    SegmentationInput input() const
    {
        SegmentationInput in;
        in.depth = &depth;
        in.color = &color;
        in.K = K;
        in.source = "test frame";
        return in;
    }
};

/// The expected labels at the network's resolution (w x h, `step` frame pixels per output pixel):
/// logits (void 0.5, wall 4r, chair 4g, table 4b); thing pixels go to the nearest centre of
/// (x + 1, y) (offset dx 0.5 × scale 2), earlier (higher) centres winning ties; then Eq. 1.
PanopticFrame expectedLabels(const Scene& s, int step, bool instances)
{
    const int w = W / step, h = H / step;
    PanopticFrame e;
    e.semantic.resize(w, h);
    e.semantic_score.resize(w, h);
    e.instance.resize(w, h);
    e.panoptic_score.resize(w, h);
    const double other = std::exp(0.5) + 2.0, win = std::exp(4.0);
    std::vector<std::array<int, 41>> votes(s.centres.size(), std::array<int, 41>{});
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
        {
            const auto c = s.color.at(y * step, x * step);
            const uint16_t cls = c[0] ? kWall : c[1] ? kChair : kTable;
            e.semantic.at(y, x) = cls;
            e.semantic_score.at(y, x) = float(win / (win + other));
            if (cls == kWall || !instances) continue;
            double best = 1e9;
            for (size_t k = 0; k < s.centres.size(); ++k)
            {
                const double dx = x + 1 - s.centres[k].x / step, dy = y - s.centres[k].y / step;
                if (dx * dx + dy * dy < best)
                {
                    best = dx * dx + dy * dy;
                    e.instance.at(y, x) = uint32_t(k + 1);
                }
            }
            ++votes[e.instance.at(y, x) - 1][cls];
        }
    for (int y = 0; y < h && instances; ++y)
        for (int x = 0; x < w; ++x)
            if (const uint32_t z = e.instance.at(y, x))
            {
                const auto& v = votes[z - 1];
                e.semantic.at(y, x) = v[kChair] >= v[kTable] ? kChair : kTable;
                e.panoptic_score.at(y, x) = e.semantic_score.at(y, x) * ((s.centres[z - 1].depth - 2.f) / 10.f);
            }
    return e;
}

void expectFrameEquals(const PanopticFrame& out, const PanopticFrame& e, int step)
{
    ASSERT_EQ(out.semantic.width, W);
    ASSERT_EQ(out.semantic.height, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
        {
            const int sy = y / step, sx = x / step;
            ASSERT_EQ(out.semantic.at(y, x), e.semantic.at(sy, sx)) << x << "," << y;
            ASSERT_NEAR(out.semantic_score.at(y, x), e.semantic_score.at(sy, sx), 2e-6);
            if (!out.hasInstances()) continue;
            ASSERT_EQ(out.instance.at(y, x), e.instance.at(sy, sx)) << x << "," << y;
            ASSERT_NEAR(out.panoptic_score.at(y, x), e.panoptic_score.at(sy, sx), 2e-6) << x << "," << y;
        }
}

std::string errorOf(const std::function<void()>& f)
{
    try
    {
        f();
    }
    catch (const InputError& e)
    {
        return e.what();
    }
    ADD_FAILURE() << "no InputError";
    return {};
}
}  // namespace

TEST(SegModels, PanopticNetworkGivesTheHandComputedLabelImages)
{
    const Scene s;
    auto seg = loadSegmenter(description("panoptic_tiny.onnx", "panoptic", W, H), nyu());
    PanopticFrame out;
    seg->segment(s.input(), out);
    const auto e = expectedLabels(s, 1, true);
    expectFrameEquals(out, e, 1);
    // Sanity of the hand computation itself: three instances, the first on chair pixels.
    EXPECT_EQ(out.instance.at(2, 10), 1u);
    EXPECT_EQ(out.semantic.at(2, 10), kChair);
    EXPECT_EQ(out.semantic.at(9, 12), kTable);
    EXPECT_EQ(out.instance.at(9, 12), 3u);
    EXPECT_EQ(out.instance.at(3, 3), 0u) << "wall is stuff";
    EXPECT_GT(seg->lastTiming().network_ms, 0.0);
    EXPECT_EQ(seg->lastDetections(), nullptr);
}

TEST(SegModels, AHalfResolutionNetworkIsFedResizedFramesAndItsLabelsScaledBack)
{
    const Scene s;
    auto seg = loadSegmenter(description("panoptic_tiny_half.onnx", "panoptic", W / 2, H / 2), nyu());
    PanopticFrame out;
    seg->segment(s.input(), out);
    expectFrameEquals(out, expectedLabels(s, 2, true), 2);
}

TEST(SegModels, SemanticOnlyNetworkGivesClassesWithoutInstances)
{
    const Scene s;
    auto seg = loadSegmenter(description("semantic_tiny.onnx", "semantic", W, H), nyu());
    PanopticFrame out;
    seg->segment(s.input(), out);
    EXPECT_TRUE(out.hasLabels());
    EXPECT_FALSE(out.hasInstances());
    expectFrameEquals(out, expectedLabels(s, 1, false), 1);
}

TEST(SegModels, BgrInputsSwapTheColourChannels)
{
    // Fed as BGR, red pixels reach the network's third channel: table instead of wall.
    const Scene s;
    auto seg = loadSegmenter(description("semantic_tiny.onnx", "semantic", W, H, "bgr"), nyu());
    PanopticFrame out;
    seg->segment(s.input(), out);
    EXPECT_EQ(out.semantic.at(0, 0), kTable);
    EXPECT_EQ(out.semantic.at(0, 15), kChair);
}

TEST(SegModels, AWrongModelFileIsAnErrorNamingItAndTheExpectedOutputs)
{
    // A network with 3 semantic channels for a description of 4 classes.
    const std::string wrong = description("panoptic_3_channels.onnx", "panoptic", W, H);
    const std::string msg = errorOf([&] { loadSegmenter(wrong, nyu()); });
    EXPECT_NE(msg.find("panoptic_3_channels.onnx"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'semantic' [1, 4, h, w]"), std::string::npos) << msg;
    EXPECT_NE(msg.find("[1, 3, 12, 16]"), std::string::npos) << msg;

    // Not an ONNX file at all.
    const auto dir = test::tempDir("corrupt");
    test::writeText(dir / "garbage.onnx", "this is not a protobuf");
    const std::string desc = test::writeText(
        dir / "m.json", R"({"format": "pndt-segmentation-model/1", "onnx": "garbage.onnx", "kind": "semantic",
        "input_size": [16, 12], "inputs": [{"name": "rgb"}], "outputs": {"semantic": "semantic"}, "classes": ["void"]})");
    const std::string corrupt = errorOf([&] { loadSegmenter(desc, nyu()); });
    EXPECT_NE(corrupt.find((dir / "garbage.onnx").string()), std::string::npos) << corrupt;

    // Missing network file.
    std::filesystem::remove(dir / "garbage.onnx");
    EXPECT_NE(errorOf([&] { loadSegmenter(desc, nyu()); }).find("does not exist"), std::string::npos);

    // An input name the network does not have.
    const std::string bad_input = test::writeText(
        dir / "m2.json", R"({"format": "pndt-segmentation-model/1", "onnx": ")" + kModels +
                             R"(/semantic_tiny.onnx", "kind": "semantic", "input_size": [16, 12],
        "inputs": [{"name": "colour"}, {"name": "depth", "kind": "depth"}], "outputs": {"semantic": "semantic"},
        "classes": ["void", "wall", "chair", "table"]})");
    EXPECT_NE(errorOf([&] { loadSegmenter(bad_input, nyu()); }).find("semantic_tiny.onnx"), std::string::npos);
}

TEST(SegModels, FramesWithoutColourOrOfTheWrongSizeAreRefused)
{
    Scene s;
    auto seg = loadSegmenter(description("panoptic_tiny.onnx", "panoptic", W, H), nyu());
    PanopticFrame out;
    auto in = s.input();
    in.color = nullptr;
    EXPECT_NE(errorOf([&] { seg->segment(in, out); }).find("test frame"), std::string::npos);
    Image<RgbPixel> small(8, 6);
    in.color = &small;
    EXPECT_NE(errorOf([&] { seg->segment(in, out); }).find("registered"), std::string::npos);
    in = s.input();
    in.K.width = 32;
    EXPECT_THROW(seg->segment(in, out), InputError);
}

TEST(SegModels, DetectorNetworkBoxesBecomeDepthSegmentInstances)
{
    // detector_tiny: heatmap[c] = 4x4 average of input channel c (chair, couch, dining table),
    // boxes ±4 input pixels around stride 4 × cell. A 4x4 green block at cell (2, 1) = pixels
    // x 8..11, y 4..7 gives one couch detection, score 128/255, box [4, 12) x [0, 8).
    const auto dir = test::tempDir("detector");
    const std::string desc = test::writeText(
        dir / "det.json", R"({"format": "pndt-segmentation-model/1", "onnx": ")" + kModels +
                              R"(/detector_tiny.onnx", "kind": "detector", "input_size": [16, 16],
        "inputs": [{"name": "rgb", "scale": 0.003921568627451}], "outputs": {"heatmap": "heatmap", "box_size": "box_size"},
        "classes": ["chair", "couch", "dining table"],
        "detector": {"score_threshold": 0.3, "top_k": 10, "stride": 4, "box_scale": 1}})");
    Image<RgbPixel> color(16, 16);
    Image<float> depth(16, 16, 3.f);
    for (int y = 4; y < 8; ++y)
        for (int x = 8; x < 12; ++x)
        {
            color.at(y, x) = {0, 128, 0};
            depth.at(y, x) = 1.f;
        }
    auto seg = loadSegmenter(desc, nyu());
    SegmentationInput in;
    in.depth = &depth;
    in.color = &color;
    in.K = {16, 16, 16, 16, 7.5, 7.5};
    in.source = "detector frame";
    PanopticFrame out;
    seg->segment(in, out);
    ASSERT_NE(seg->lastDetections(), nullptr);
    ASSERT_EQ(seg->lastDetections()->size(), 1u);
    const Detection& d = seg->lastDetections()->front();
    EXPECT_EQ(d.model_class, 1);
    EXPECT_NEAR(d.score, 128.f / 255.f, 1e-5);
    EXPECT_FLOAT_EQ(d.x0, 4.f);
    EXPECT_FLOAT_EQ(d.y0, 0.f);
    EXPECT_FLOAT_EQ(d.x1, 12.f);
    EXPECT_FLOAT_EQ(d.y1, 8.f);
    // The instance is the near block inside the box, as a sofa (COCO couch → NYUv2-40 sofa).
    ASSERT_TRUE(out.hasInstances());
    for (int y = 4; y < 8; ++y)
        for (int x = 8; x < 12; ++x)
        {
            EXPECT_EQ(out.semantic.at(y, x), 6) << x << "," << y;
            EXPECT_EQ(out.instance.at(y, x), 1u);
            EXPECT_NEAR(out.panoptic_score.at(y, x), d.score * d.score, 1e-6);
        }
    EXPECT_EQ(out.instance.at(2, 6), 0u) << "background inside the box is not the object";
    EXPECT_EQ(out.instance.at(12, 12), 0u);
}
