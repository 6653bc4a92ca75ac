// The model description file: every key read, and every mistake a clear error naming the file.
#include <gtest/gtest.h>
#include <pndt/seg/detector_geometry.h>
#include <pndt/seg/model_description.h>

#include <set>

#include "seg_test_util.h"

using namespace pndt;
using namespace pndt::seg;

namespace
{
const char* kPanoptic = R"({
  "format": "pndt-segmentation-model/1",
  "name": "test",
  "onnx": "net.onnx",
  "kind": "panoptic",
  "input_size": [640, 480],
  "inputs": [{"name": "rgb", "kind": "rgb", "scale": 0.00392156862, "mean": [0.485, 0.456, 0.406],
              "std": [0.229, 0.224, 0.225]},
             {"name": "depth", "kind": "depth", "mean": [2.5], "std": [1.5]}],
  "outputs": {"semantic": "sem", "center": "ctr", "offset": "off"},
  "classes": ["void", "wall", "chair"],
  "postprocess": {"center_threshold": 0.2, "nms_kernel": 7, "top_k": 10, "center_activation": "sigmoid",
                  "offset_order": "xy", "offset_scale": 0.5}
})";

std::string expectError(const std::string& text, const std::string& name)
{
    const auto dir = test::tempDir("desc_" + name);
    const std::string path = test::writeText(dir / "model.json", text);
    try
    {
        loadModelDescription(path);
    }
    catch (const InputError& e)
    {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(path), std::string::npos) << "the error names the file: " << msg;
        return msg;
    }
    ADD_FAILURE() << "accepted: " << text;
    return {};
}

std::string replaced(std::string s, const std::string& from, const std::string& to)
{
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
}
}  // namespace

TEST(ModelDescription, ReadsEveryKey)
{
    const auto dir = test::tempDir("desc_ok");
    const auto d = loadModelDescription(test::writeText(dir / "model.json", kPanoptic));
    EXPECT_EQ(d.kind, "panoptic");
    EXPECT_EQ(d.onnx_path, (dir / "net.onnx").string()) << "relative to the description file";
    EXPECT_EQ(d.input_width, 640);
    EXPECT_EQ(d.input_height, 480);
    ASSERT_EQ(d.inputs.size(), 2u);
    EXPECT_EQ(d.inputs[0].mean.size(), 3u);
    EXPECT_FLOAT_EQ(d.inputs[0].std[2], 0.225f);
    EXPECT_EQ(d.inputs[1].kind, "depth");
    EXPECT_EQ(d.outputNames(), (std::vector<std::string>{"sem", "ctr", "off"}));
    EXPECT_FLOAT_EQ(d.postprocess.center_threshold, 0.2f);
    EXPECT_EQ(d.postprocess.nms_kernel, 7);
    EXPECT_EQ(d.postprocess.top_k, 10);
    EXPECT_TRUE(d.postprocess.center_is_logit);
    EXPECT_FALSE(d.postprocess.offset_yx);
    EXPECT_FLOAT_EQ(d.postprocess.offset_scale, 0.5f);
    EXPECT_EQ(mapModelClasses(d, ClassSet::nyuv2_40()), (std::vector<uint16_t>{0, 1, 5}));
}

TEST(ModelDescription, MistakesAreErrorsNamingTheFileAndTheKey)
{
    EXPECT_NE(expectError("{ not json", "json").find("not valid JSON"), std::string::npos);
    EXPECT_NE(expectError(replaced(kPanoptic, "\"top_k\"", "\"topk\""), "typo").find("unknown key 'topk'"),
              std::string::npos);
    EXPECT_NE(expectError(replaced(kPanoptic, "pndt-segmentation-model/1", "v2"), "format").find("format"),
              std::string::npos);
    EXPECT_NE(expectError(replaced(kPanoptic, "\"center\": \"ctr\", ", ""), "center").find("'center'"),
              std::string::npos);
    EXPECT_NE(expectError(replaced(kPanoptic, "\"nms_kernel\": 7", "\"nms_kernel\": 8"), "kernel").find("odd"),
              std::string::npos);
    EXPECT_NE(expectError(replaced(kPanoptic, "\"panoptic\"", "\"instance\""), "kind").find("panoptic | semantic"),
              std::string::npos);
    EXPECT_NE(expectError(replaced(kPanoptic, "[640, 480]", "[640]"), "size").find("input_size"), std::string::npos);
    EXPECT_NE(expectError(replaced(kPanoptic, "\"std\": [1.5]", "\"std\": [0]"), "std").find("std"),
              std::string::npos);
    EXPECT_NE(expectError(replaced(kPanoptic, "[0.485, 0.456, 0.406]", "[0.4, 0.4]"), "mean").find("1 or 3"),
              std::string::npos);
    EXPECT_NE(expectError(replaced(kPanoptic, "\"top_k\": 10", "\"top_k\": \"ten\""), "type").find("wrong type"),
              std::string::npos);
    const auto missing = test::tempDir("desc_missing") / "nothing.json";
    EXPECT_THROW(loadModelDescription(missing.string()), InputError);
}

TEST(ModelDescription, AClassOutsideTheClassSetIsNamed)
{
    const auto dir = test::tempDir("desc_class");
    const auto d = loadModelDescription(test::writeText(dir / "m.json", replaced(kPanoptic, "\"chair\"", "\"chairs\"")));
    try
    {
        mapModelClasses(d, ClassSet::nyuv2_40());
        FAIL();
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("'chairs'"), std::string::npos) << e.what();
    }
}

// The COCO-80 names live twice: in the detector's class check (detector_classes.cpp) and in the
// fetch script's description writer (scripts/models/write_description.py, which the test build
// runs). The description that script writes must load and map every class with no class_map.
TEST(ModelDescription, TheFetchScriptsCocoDescriptionLoadsAndMapsEveryClass)
{
    const auto d = loadModelDescription(PNDT_SEG_COCO_DESCRIPTION);
    EXPECT_EQ(d.kind, "detector");
    ASSERT_EQ(d.classes.size(), 80u);
    EXPECT_EQ(std::set<std::string>(d.classes.begin(), d.classes.end()).size(), 80u) << "names once";
    EXPECT_EQ(d.classes[0], "person") << "COCO-80 detection order";
    EXPECT_EQ(d.classes[56], "chair");
    EXPECT_EQ(d.classes[79], "toothbrush");
    std::vector<uint16_t> ids;
    ASSERT_NO_THROW(ids = mapDetectorClasses(d.classes, d.class_map, ClassSet::nyuv2_40()));
    ASSERT_EQ(ids.size(), 80u);
    const auto& nyu = ClassSet::nyuv2_40();
    EXPECT_EQ(ids[0], nyu.find("person"));
    EXPECT_EQ(ids[56], nyu.find("chair"));
    EXPECT_EQ(ids[57], nyu.find("sofa")) << "couch";
    EXPECT_EQ(ids[23], nyu.find("otherprop")) << "giraffe: no indoor counterpart";
}
