// pndt-eval: score any map (or every map of a pndt-map output folder) against a user's
// ground truth, with the metrics and formats of design §9 — doc/pndt-eval.md.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <pndt/app/cli_numbers.h>
#include <pndt/eval/label_text.h>
#include <pndt/io/atomic_file.h>
#include <pndt/mrpt/map_files.h>

#include <filesystem>
#include <iostream>

#include "evaluate_cloud.h"
#include "evaluate_frames.h"
#include "map_inputs.h"
#include "scores_output.h"

using namespace pndt;
namespace fs = std::filesystem;

namespace
{
/// Exit codes: 0 scored, 1 bad input (named in the message), 2 bad command line (CLI11).
constexpr int kBadInput = 1;

eval::Benchmark benchmarkNamed(const std::string& name)
{
    if (name == "nyuv2-40") return eval::Benchmark::nyuv2_40();
    return eval::Benchmark::scannet20();
}

eval::GtPoints readGroundTruth(const std::string& gt_ply, const std::string& points_ply, const std::string& gt_text,
                               uint32_t shift, const eval::Benchmark& bench)
{
    eval::GtPoints gt;
    if (!gt_ply.empty())
        gt = eval::readPlyPoints(gt_ply, true);
    else
    {
        gt = eval::readPlyPoints(points_ply, false);
        gt.labels = eval::panopticFromShifted(eval::readLabelText(gt_text), shift, gt_text);
        if (gt.labels.size() != gt.points.size())
            throw InputError(fmt::format("{} has {} labels but {} has {} vertices: they must match line for vertex",
                                         gt_text, gt.labels.size(), points_ply, gt.points.size()));
    }
    // Checked here, naming the file, before any map is loaded (a wrong --gt-shift is the likely cause).
    const size_t classes = bench.classes().size();
    for (size_t i = 0; i < gt.labels.size(); ++i)
        if ((gt.labels[i] >> 16) >= classes)
            throw InputError(fmt::format(
                "{}: {} {}: class {} is outside the benchmark's classes 0..{}{}", gt_ply.empty() ? gt_text : gt_ply,
                gt_ply.empty() ? "line" : "vertex", gt_ply.empty() ? i + 1 : i, gt.labels[i] >> 16, classes - 1,
                gt_ply.empty() ? fmt::format(" (label {} with --gt-shift {}: is the shift right?)",
                                             uint64_t(gt.labels[i] >> 16) * shift + (gt.labels[i] & 0xFFFF), shift)
                               : ""));
    return gt;
}
/// The benchmark's tables score class ids by its own class set: a map of another set (other
/// names, or other thing flags) would be scored as if its ids were the benchmark's classes.
void requireBenchmarkClasses(const ClassSet& map_classes, const eval::Benchmark& bench, const std::string& path)
{
    const ClassSet& b = bench.classes();
    if (map_classes == b) return;
    std::string diff;
    if (map_classes.size() != b.size())
        diff = fmt::format("{} classes against the benchmark's {}", map_classes.size(), b.size());
    else
        for (uint32_t i = 0; i < b.size() && diff.empty(); ++i)
            if (map_classes.name(i) != b.name(i) || map_classes.isThing(i) != b.isThing(i))
                diff = fmt::format("class {} is '{}' ({}) where the benchmark has '{}' ({})", i, map_classes.name(i),
                                   map_classes.isThing(i) ? "thing" : "stuff", b.name(i),
                                   b.isThing(i) ? "thing" : "stuff");
    throw InputError(fmt::format("{}: the map's class set is not the one of the benchmark table '{}' ({}): its "
                                 "class ids would be scored as other classes",
                                 path, bench.name(), diff));
}
}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"pndt-eval: score PanopticNDT maps against your ground truth (3D points and/or 2D frames)"};
    std::string map_arg, gt_ply, points_ply, gt_text, nicr_dir, nicr_seq, classes = "nyuv2-40", json_path, export_dir;
    uint32_t shift = 65536;
    int every = 1;
    double min_labelled = 0.05;
    bool tables = true;
    app.add_option("map", map_arg, "a map (.pndt.gz) or a pndt-map output folder (every map in its index.json)")
        ->required();
    auto* o_ply = app.add_option("--gt-ply", gt_ply, "3D GT: PLY points with a `label` property (sem << 16 | ins)");
    auto* o_pts = app.add_option("--points", points_ply, "3D GT points without labels (e.g. a ScanNet *_vh_clean_2.ply)");
    auto* o_txt = app.add_option("--gt-text", gt_text, "labels of --points, one per line (sem * shift + ins)");
    app.add_option("--gt-shift", shift, "the shift of --gt-text labels: 65536 (nicr, default) or 1000 (ScanNet's own)")
        ->check(CLI::IsMember({1000u, 65536u}));
    app.add_option("--nicr", nicr_dir, "2D GT: a nicr-layout split folder (<dataset>/<split>)");
    auto* o_seq = app.add_option("--sequence", nicr_seq, "the sequence in --nicr (e.g. ai_001_010/cam_00)");
    app.add_option("--every", every, "2D: evaluate every k-th frame")->check(app::kPositive);
    app.add_option("--classes", classes, "benchmark class table")->check(CLI::IsMember({"nyuv2-40", "scannet-20"}));
    app.add_option("--min-labelled", min_labelled,
                   "refuse a 3D evaluation where the map labels fewer GT points than this share (wrong frame or scene)")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--json", json_path, "also write the scores as JSON");
    app.add_option("--export", export_dir, "write the predictions in the ScanNet benchmark formats below this folder");
    bool no_tables = false;  // a plain flag: CLI11 shows a negated one as "--no-tables{false}"
    app.add_flag("--no-tables", no_tables, "print only the summary lines");
    o_ply->excludes(o_pts);
    o_pts->needs(o_txt);
    o_txt->needs(o_pts);
    o_seq->needs("--nicr");
    CLI11_PARSE(app, argc, argv);
    tables = !no_tables;
    if (gt_ply.empty() && points_ply.empty() && nicr_dir.empty())
    {
        std::cerr << "pndt-eval: give 3D ground truth (--gt-ply, or --points with --gt-text) and/or 2D (--nicr)\n";
        return 2;
    }
    if (!nicr_dir.empty() && nicr_seq.empty())
    {
        std::cerr << "pndt-eval: --nicr needs --sequence\n";
        return 2;
    }

    try
    {
        const eval::Benchmark bench = benchmarkNamed(classes);
        const std::vector<std::string> maps = evalapp::mapFiles(map_arg);
        eval::GtPoints gt;
        const bool three_d = !gt_ply.empty() || !points_ply.empty();
        if (three_d) gt = readGroundTruth(gt_ply, points_ply, gt_text, shift, bench);
        nlohmann::json out = nlohmann::json::array();
        for (const std::string& path : maps)
        {
            const auto map = loadMapArchive(path);
            const PanopticMap& core = map->core();
            requireBenchmarkClasses(core.options().classes, bench, path);
            nlohmann::json j;
            j["map"] = path;
            j["classes"] = classes;
            j["instances"] = core.instances().size();
            std::cout << fmt::format("{}: {} voxels, {} instances\n", path, core.voxels().size(), core.instances().size());
            const std::string name = fs::path(path).stem().stem().string();
            if (three_d)
            {
                const evalapp::CloudScores s = evalapp::evaluateCloud(
                    core, gt, bench, export_dir.empty() ? "" : (fs::path(export_dir) / "3d").string(), name);
                std::cout << fmt::format("  3D ({} GT points, {:.1f} % labelled by the map): {}\n", s.points,
                                         100 * s.labelledShare(), evalapp::summaryLine(s.result));
                if (s.labelledShare() < min_labelled)
                    throw InputError(fmt::format(
                        "{}: the map labels only {:.1f} % of the {} GT points (--min-labelled {:.0f} %): is it the "
                        "same scene, in the same frame?",
                        path, 100 * s.labelledShare(), s.points, 100 * min_labelled));
                if (tables) std::cout << evalapp::classTable(s.result, bench) << "\n";
                j["3d"] = evalapp::scoresJson(s.result, bench);
                j["3d"]["points"] = s.points;
                j["3d"]["labelled_share"] = s.labelledShare();
            }
            if (!nicr_dir.empty())
            {
                const evalapp::FrameScores s = evalapp::evaluateFrames(
                    core, nicr_dir, nicr_seq, bench, every, export_dir.empty() ? "" : (fs::path(export_dir) / "2d").string());
                std::cout << fmt::format("  2D ({} frames; {} without pose, {} without GT skipped): {}\n", s.frames,
                                         s.skipped_no_pose, s.skipped_no_gt, evalapp::summaryLine(s.result));
                if (tables) std::cout << evalapp::classTable(s.result, bench) << "\n";
                j["2d"] = evalapp::scoresJson(s.result, bench);
                j["2d"]["frames"] = s.frames;
            }
            out.push_back(j);
        }
        if (!json_path.empty()) io::writeFileAtomically(json_path, out.dump(2) + "\n");
    }
    catch (const std::exception& e)
    {
        std::cerr << "pndt-eval: " << e.what() << "\n";
        return kBadInput;
    }
    return 0;
}
