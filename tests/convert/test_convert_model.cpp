// pndt-convert --model: an unlabelled Redwood folder labelled by the segmentation front-end
// (a tiny semantic ONNX model from tests/seg/make_test_models.py with hand-computable logits).
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "convert_fixtures.h"

using namespace pndt;
using namespace pndt::convert::test;
using mrpt::obs::CObservation3DRangeScan;
using mrpt::obs::CObservationImage;

namespace
{
RunResult runConvert(const std::vector<std::string>& args) { return runExe(PNDT_CONVERT_EXE, args); }

/// semantic_tiny.onnx (16x12 input): logits void 0.5, wall 4r, chair 4g, table 4b of the colour
/// scaled to [0, 1]; its depth input is unused by the semantic output.
std::string tinySemanticModel(const std::string& dir)
{
    const std::string p = (fs::path(dir) / "tiny.json").string();
    std::ofstream(p) << R"({"format": "pndt-segmentation-model/1", "name": "tiny", "onnx": ")" PNDT_SEG_TEST_MODELS
                        R"(/semantic_tiny.onnx", "kind": "semantic", "input_size": [16, 12],
      "inputs": [{"name": "rgb", "kind": "rgb", "scale": 0.003921568627451},
                 {"name": "depth", "kind": "depth", "mean": [2], "std": [10]}],
      "outputs": {"semantic": "semantic"}, "classes": ["void", "wall", "chair", "table"]})";
    return p;
}
}  // namespace

using ConvertModel = TempDirTest;

TEST_F(ConvertModel, AnUnlabelledRecordingGetsTheNetworksLabelImages)
{
    // Fixture frame i is uniformly RGB (200, 100, 10 i): wall wins with
    // S^L = e^(4·200/255) / (e^0.5 + e^(4·200/255) + e^(4·100/255) + e^(4·10i/255)).
    const std::string in = makeRedwoodFolder(folder("redwood"));
    const std::string out = path("out.rawlog"), js = path("s.json");
    const RunResult r = runConvert({in, "-o", out, "--model", tinySemanticModel(dir()), "--summary-json", js, "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    EXPECT_TRUE(contains(r.out, "segmentation       : semantic network 'tiny'")) << r.out;
    const auto j = nlohmann::json::parse(slurp(js));
    EXPECT_EQ(j["frames_with_labels"], 3);
    EXPECT_EQ(j["segmentation"]["frames"], 3);

    const auto objs = readRawlog(out);
    ASSERT_EQ(objs.size(), 12u);  // (pose, scan, semantic, instance) x 3
    for (int i = 0; i < 3; ++i)
    {
        const auto sem = std::dynamic_pointer_cast<CObservationImage>(objs[size_t(4 * i + 2)]);
        const auto ins = std::dynamic_pointer_cast<CObservationImage>(objs[size_t(4 * i + 3)]);
        ASSERT_TRUE(sem && ins) << "frame " << i;
        EXPECT_EQ(sem->sensorLabel, "RGBD_PANOPTIC_SEMANTIC");
        const double r8 = 200 / 255.0, g8 = 100 / 255.0, b8 = 10 * i / 255.0;
        const double sl = std::exp(4 * r8) / (std::exp(0.5) + std::exp(4 * r8) + std::exp(4 * g8) + std::exp(4 * b8));
        ASSERT_EQ(sem->image.getWidth(), size_t(kW));
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
            {
                ASSERT_NEAR(sem->image.ptrLine<float>(y)[x], 1.0 + sl, 1e-5) << x << "," << y;
                ASSERT_EQ(ins->image.ptrLine<float>(y)[x], 0.f) << "a semantic model gives no instances";
            }
    }
}

TEST_F(ConvertModel, ABadModelStopsTheConversionNamingTheFile)
{
    const std::string in = makeRedwoodFolder(folder("redwood"));
    const std::string out = path("out.rawlog");
    const std::string missing = path("nothing.json");
    RunResult r = runConvert({in, "-o", out, "--model", missing, "-q"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.err, missing)) << r.err;
    EXPECT_FALSE(fs::exists(out));

    r = runConvert({in, "-o", out, "--model", tinySemanticModel(dir()), "--labels", "gt", "-q"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.err, "--model")) << r.err;

    r = runConvert({in, "-o", out, "--model", tinySemanticModel(dir()), "--up", "0 0", "-q"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.err, "--up")) << r.err;
}
