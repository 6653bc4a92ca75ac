// The results.md writer of pndt-experiments keeps the hand-written text outside its markers.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "report.h"

namespace fs = std::filesystem;

namespace
{
std::string slurp(const fs::path& p)
{
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}
}  // namespace

TEST(ExperimentReport, KeepsTextOutsideTheMarkers)
{
    const fs::path dir = fs::temp_directory_path() / ("pndt_exp_report_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path md = dir / "results.md";
    pndt::exp::writeReport(md.string(), "first\n");
    std::string text = slurp(md);
    EXPECT_NE(text.find("first\n"), std::string::npos);
    // Hand-written text before and after the block survives a rewrite.
    text = "# Title\nintro\n" + text.substr(text.find("<!-- BEGIN")) + "\nmy discussion\n";
    std::ofstream(md) << text;
    pndt::exp::writeReport(md.string(), "second\n");
    const std::string again = slurp(md);
    EXPECT_EQ(again.find("first"), std::string::npos);
    EXPECT_NE(again.find("second\n"), std::string::npos);
    EXPECT_EQ(again.rfind("# Title\nintro\n", 0), 0u);
    EXPECT_NE(again.find("my discussion"), std::string::npos);
    // A file without markers is not overwritten.
    const fs::path other = dir / "other.md";
    std::ofstream(other) << "precious\n";
    EXPECT_THROW(pndt::exp::writeReport(other.string(), "x\n"), std::runtime_error);
    EXPECT_EQ(slurp(other), "precious\n");
    fs::remove_all(dir);
}

TEST(ExperimentReport, RowsCoverTheTableShape)
{
    pndt::exp::Plan plan;
    plan.voxels = {0.05, 0.1, 0.2};
    const auto rows = pndt::exp::makeRows(plan);
    auto has = [&](const std::string& id) {
        for (const auto& r : rows)
            if (r.id == id) return true;
        return false;
    };
    for (const char* id : {"raw-net", "raw-gt", "ndt-net@5cm", "ndt-net@10cm", "ndt-net@20cm", "cube-net@10cm",
                           "noprop-net@10cm", "ndt-gt@20cm", "semonly-net@10cm", "thr-0.1-0.05@10cm",
                           "thr-0.3-0.15@10cm", "paper-instances@10cm", "nofill-net@10cm",
                           "perpixel-net@10cm", "paper-net@5cm", "paper-net@10cm", "paper-net@20cm"})
        EXPECT_TRUE(has(id)) << id;
    EXPECT_FALSE(has("tuned-net@10cm"));
    for (const auto& r : rows)
    {
        if (r.id == "cube-net@10cm")
        {
            EXPECT_FALSE(r.options.use_ndt);
        }
        if (r.id == "thr-0.1-0.05@10cm")
        {
            EXPECT_DOUBLE_EQ(r.options.theta_m, 0.1);
        }
        if (r.id == "paper-instances@10cm")
        {
            EXPECT_FALSE(r.options.class_consistent_instances);
            EXPECT_EQ(r.options.split_coverage, 0.0);
            EXPECT_EQ(r.options.fragment_merge_frames, 0u);
            EXPECT_EQ(r.options.fragment_absorb_ratio, 0.0);
        }
        if (r.id == "nofill-net@10cm")
        {
            EXPECT_EQ(r.options.label_fill_distance, 0.0);
        }
        if (r.id == "perpixel-net@10cm")
        {
            EXPECT_EQ(r.options.ray_mode, pndt::RayMode::PerPixel);
            EXPECT_EQ(r.options.label_fill_distance, 0.2);  // only the rays differ from the reference
        }
        if (r.id == "paper-net@20cm")
        {
            pndt::MapOptions paper;
            paper.applyPaperRules();
            EXPECT_EQ(r.options.voxel_size, 0.2);
            EXPECT_EQ(r.options.ray_mode, paper.ray_mode);
            EXPECT_EQ(r.options.miss_accumulation, paper.miss_accumulation);
            EXPECT_EQ(r.options.semantic_eviction, paper.semantic_eviction);
            EXPECT_EQ(r.options.instance_class_voxels, paper.instance_class_voxels);
            EXPECT_FALSE(r.options.class_consistent_instances);
            EXPECT_EQ(r.options.label_fill_distance, 0.0);
        }
        if (r.id == "noprop-net@10cm")
        {
            EXPECT_EQ(r.map_key, "ndt-net@10cm");
        }
        if (!r.raw)
        {
            EXPECT_DOUBLE_EQ(r.options.theta_l, 0.7);
        }
    }
    plan.tuned_theta_l = 0.3;
    const auto tuned = pndt::exp::makeRows(plan);
    size_t n = 0;
    for (const auto& r : tuned)
        if (r.id.rfind("tuned-net@", 0) == 0)
        {
            ++n;
            EXPECT_DOUBLE_EQ(r.options.theta_l, 0.3);
        }
    EXPECT_EQ(n, 3u);
}

TEST(ExperimentReport, RuleThresholdsChosenOnValidationReachEveryMapRow)
{
    pndt::exp::Plan plan;
    plan.voxels = {0.1};
    plan.rules.split_coverage = 0.7;
    plan.rules.fragment_merge_frames = 5;
    plan.rules.fragment_absorb_ratio = 0.1;
    plan.rules.label_fill_distance = 0.5;
    for (const auto& r : pndt::exp::makeRows(plan))
    {
        if (r.raw || r.id.rfind("paper", 0) == 0 || r.id == "nofill-net@10cm") continue;
        EXPECT_EQ(r.options.split_coverage, 0.7) << r.id;
        EXPECT_EQ(r.options.fragment_merge_frames, 5u) << r.id;
        EXPECT_EQ(r.options.fragment_absorb_ratio, 0.1) << r.id;
        EXPECT_EQ(r.options.label_fill_distance, 0.5) << r.id;
    }
}

TEST(ExperimentReport, ValidationSweepsOneParameterAtATime)
{
    pndt::exp::Plan plan;
    plan.voxels = {0.1};
    const double split_default = pndt::MapOptions{}.split_coverage;
    ASSERT_NE(split_default, 0.3);
    const pndt::exp::Sweep sweep = {{"theta_l", {0.5, 0.7}}, {"split_coverage", {0.3, split_default}}};
    const auto rows = pndt::exp::makeValidationRows(plan, sweep);
    // raw input, theta_L 0.5, the defaults' map (theta_L 0.7 = split at its default), split 0.3.
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(pndt::exp::validationRowId("split_coverage", split_default), pndt::exp::validationRowId(0.7));
    for (const auto& r : rows)
    {
        if (r.id == pndt::exp::validationRowId("split_coverage", 0.3))
        {
            EXPECT_EQ(r.options.split_coverage, 0.3);
            EXPECT_EQ(r.options.theta_l, 0.7);
        }
        if (r.id == pndt::exp::validationRowId(0.5))
        {
            EXPECT_EQ(r.options.theta_l, 0.5);
            EXPECT_EQ(r.options.split_coverage, split_default);
        }
    }
    // Choosing: the best criterion, ties to the default.
    pndt::exp::ValidationResult v;
    v.sweep = sweep;
    pndt::exp::RunResult run;
    auto set = [&](const std::string& id, double x) {
        pndt::exp::Scores s;
        s.miou3 = s.pq3 = s.miou2 = s.pq2 = x;
        run.scores[id] = s;
    };
    set(pndt::exp::validationRowId(0.7), 50);
    set(pndt::exp::validationRowId(0.5), 50);
    set(pndt::exp::validationRowId("split_coverage", 0.3), 51);
    v.runs = {run};
    EXPECT_EQ(pndt::exp::chooseThetaL(v), 0.7);
    EXPECT_EQ(pndt::exp::chooseValue(v, "split_coverage"), 0.3);
    // A gain within the tie margin keeps the default.
    set(pndt::exp::validationRowId("split_coverage", 0.3), 50 + 0.5 * pndt::exp::kValidationTieMargin);
    v.runs = {run};
    EXPECT_EQ(pndt::exp::chooseValue(v, "split_coverage"), split_default);
}
