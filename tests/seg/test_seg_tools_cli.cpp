// pndt-model-check and pndt-seg-bench as a user runs them on a model of their own: a checking
// tool must fail on a broken network, and no option value may crash it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "seg_test_util.h"

namespace
{
const std::string kModels = PNDT_SEG_TEST_MODELS;

std::string slurp(const std::filesystem::path& p)
{
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Runs `command` with stdout and stderr into `dir`; returns the exit code.
int run(const std::filesystem::path& dir, const std::string& command, std::string& out, std::string& err)
{
    const int rc = std::system((command + " > " + (dir / "out.txt").string() + " 2> " + (dir / "err.txt").string()).c_str());
    out = slurp(dir / "out.txt");
    err = slurp(dir / "err.txt");
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : 128 + WTERMSIG(rc);
}

std::string description(const std::filesystem::path& dir, const std::string& onnx)
{
    return pndt::seg::test::writeText(dir / "model.json", R"({"format": "pndt-segmentation-model/1", "name": "tiny",
      "onnx": ")" + onnx + R"(", "kind": "semantic", "input_size": [16, 12],
      "inputs": [{"name": "rgb", "kind": "rgb", "scale": 0.003921568627451},
                 {"name": "depth", "kind": "depth", "mean": [2], "std": [10]}],
      "outputs": {"semantic": "semantic"}, "classes": ["void", "wall", "chair", "table"]})");
}
}  // namespace

TEST(SegToolsCli, ModelCheckLoadsTheNetworkAndFailsOnABrokenOne)
{
    const auto dir = pndt::seg::test::tempDir("model_check");
    std::string out, err;
    const std::string good = description(dir, kModels + "/semantic_tiny.onnx");
    ASSERT_EQ(run(dir, std::string(PNDT_MODEL_CHECK_EXE) + " --model " + good, out, err), 0) << out << err;
    EXPECT_NE(out.find("the network loads"), std::string::npos) << out;

    // The same description over an .onnx cut to 300 bytes (before: exit 0, no output).
    std::ifstream in(kModels + "/semantic_tiny.onnx", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto cut = dir / "cut.onnx";
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, 300);
    const std::string broken = description(dir, cut.string());
    EXPECT_EQ(run(dir, std::string(PNDT_MODEL_CHECK_EXE) + " --model " + broken, out, err), 1) << out << err;
    EXPECT_NE(err.find("cut.onnx"), std::string::npos) << err;

    EXPECT_NE(run(dir, std::string(PNDT_MODEL_CHECK_EXE) + " --model " + good + " --recording x --frames 0", out, err), 0);
    EXPECT_NE(err.find("--frames"), std::string::npos) << err;
}

TEST(SegToolsCli, SegBenchRefusesZeroFramesInsteadOfCrashing)
{
    const auto dir = pndt::seg::test::tempDir("seg_bench");
    std::string out, err;
    for (const char* frames : {"0", "-3"})
    {
        const int rc = run(dir, std::string(PNDT_SEG_BENCH_EXE) + " --input scene --frames " + frames, out, err);
        EXPECT_NE(rc, 0) << frames;
        EXPECT_LT(rc, 128) << frames << ": a signal (before: a segfault, 139)";
        EXPECT_NE(err.find("--frames"), std::string::npos) << err;
    }
}
