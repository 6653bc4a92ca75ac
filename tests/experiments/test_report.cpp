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
                           "perpixel-net@10cm"})
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
            EXPECT_EQ(r.options.label_fill_distance, 0.3);  // only the rays differ from the reference
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
