#include "report.h"

#include <fmt/format.h>
#include <pndt/eval/bar_chart.h>
#include <pndt/eval/class_table.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace pndt::exp
{
namespace
{
const char* kBegin = "<!-- BEGIN pndt-experiments (generated: edit outside these markers) -->";
const char* kEnd = "<!-- END pndt-experiments -->";

std::string cm(double voxel) { return fmt::format("{:g}cm", std::round(voxel * 1000.0) / 10.0); }
std::string cmLabel(double voxel) { return voxel > 0 ? fmt::format("{:g} cm", std::round(voxel * 1000.0) / 10.0) : "–"; }

struct Stat
{
    double mean = kNaN, sd = kNaN;
    size_t n = 0;
};

Stat stat(const std::vector<double>& v)
{
    Stat s;
    double sum = 0;
    for (double x : v)
        if (!std::isnan(x)) sum += x, ++s.n;
    if (s.n == 0) return s;
    s.mean = sum / double(s.n);
    double q = 0;
    for (double x : v)
        if (!std::isnan(x)) q += (x - s.mean) * (x - s.mean);
    s.sd = s.n > 1 ? std::sqrt(q / double(s.n - 1)) : 0.0;
    return s;
}

std::string fmtStat(const Stat& s, bool spread)
{
    if (s.n == 0 || std::isnan(s.mean)) return "–";
    if (!spread || s.n < 2) return fmt::format("{:.1f}", s.mean);
    return fmt::format("{:.1f} ± {:.1f}", s.mean, s.sd);
}

std::string fmtVal(double v) { return std::isnan(v) ? "–" : fmt::format("{:.1f}", v); }
std::string fmtDelta(double v) { return std::isnan(v) ? "–" : fmt::format("{:+.1f}", v); }

using Field = double Scores::*;

std::vector<double> values(const std::vector<RunResult>& runs, const std::string& id, Field f)
{
    std::vector<double> v;
    for (const RunResult& r : runs)
    {
        auto it = r.scores.find(id);
        v.push_back(it == r.scores.end() ? kNaN : it->second.*f);
    }
    return v;
}

const RowSpec* findRow(const Plan& plan, const std::string& id)
{
    for (const RowSpec& r : plan.rows)
        if (r.id == id) return &r;
    return nullptr;
}

/// The raw-input row a map row is compared with (the input it was fed).
std::string rawOf(const RowSpec& r) { return r.input == Input::GroundTruth ? "raw-gt" : "raw-net"; }

std::string tableHeader()
{
    return "| method | voxel | 3D mIoU | 3D mIoU_P | 3D PQ | 3D AP50 (scores 1) | 3D AP50 (confidence) | 2D mIoU | 2D PQ | "
           "input 2D mIoU | input 2D PQ |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|\n";
}

std::string tableRow(const Plan& plan, const std::vector<RunResult>& runs, const std::string& id, bool spread,
                     const std::string& label_override = {})
{
    const RowSpec* r = findRow(plan, id);
    if (!r) return {};
    auto cell = [&](Field f) { return fmtStat(stat(values(runs, id, f)), spread); };
    const std::string raw = r->raw ? id : rawOf(*r);
    std::string label = label_override.empty() ? r->label : label_override;
    if (r->raw) label = r->input == Input::GroundTruth ? "GT segmentation, raw per frame" : "network-like input, raw per frame";
    return fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", label, cmLabel(r->voxel),
                       cell(&Scores::miou3), cell(&Scores::miou_p3), cell(&Scores::pq3), cell(&Scores::ap50_3),
                       cell(&Scores::ap50_3s),
                       cell(&Scores::miou2), cell(&Scores::pq2),
                       fmtStat(stat(values(runs, raw, &Scores::miou2)), spread),
                       fmtStat(stat(values(runs, raw, &Scores::pq2)), spread));
}

std::string segHeader()
{
    return "| labelling | GT things | matched | missed | wrong class | split | oversized | fragments / GT | "
           "pred. things | false pos. | FP causes: on stuff / wrong class / duplicate / poor overlap |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|\n";
}

std::string segRow(const std::string& label, const SegmentStats& s)
{
    return fmt::format("| {} | {} | {:.1f} % | {:.1f} % | {:.1f} % | {:.1f} % | {:.1f} % | {:.2f} | {} | {:.1f} % | "
                       "{:.0f} / {:.0f} / {:.0f} / {:.0f} % |\n",
                       label, s.gt_segments, s.share(s.matched), s.share(s.missed), s.share(s.wrong_class),
                       s.share(s.split), s.share(s.oversized), s.meanFragments(), s.pred_segments,
                       s.pred_segments ? 100.0 * double(s.pred_false) / double(s.pred_segments) : 0.0,
                       s.fpShare(s.fp_stuff), s.fpShare(s.fp_class), s.fpShare(s.fp_duplicate),
                       s.fpShare(s.fp_overlap));
}

SegmentStats sumSeg(const std::vector<RunResult>& runs, const std::string& id, bool three_d)
{
    SegmentStats s;
    for (const RunResult& r : runs)
    {
        const auto& m = three_d ? r.seg3d : r.seg2d;
        auto it = m.find(id);
        if (it != m.end()) s += it->second;
    }
    return s;
}

std::string shortPath(const std::string& from_dir, const std::string& file)
{
    std::error_code ec;
    const fs::path rel = fs::relative(fs::absolute(file), fs::absolute(from_dir), ec);
    return ec || rel.empty() ? file : rel.generic_string();
}
}  // namespace

std::string summaryLines(const Plan& plan, const RunResult& run)
{
    std::string out;
    for (const RowSpec& r : plan.rows)
    {
        auto it = run.scores.find(r.id);
        if (it == run.scores.end()) continue;
        const Scores& s = it->second;
        const Scores& raw = run.scores.at(r.raw ? r.id : rawOf(r));
        out += fmt::format("    {:<34} {:>6}  3D mIoU {:>5} mIoU_P {:>5} PQ {:>5} AP50 {:>5} (scored {:>5}) | 2D mIoU "
                           "{:>5} PQ {:>5} | input 2D mIoU {:>5} PQ {:>5}\n",
                           (r.group == "gt" ? "[GT input] " : "") + r.label, r.raw ? "" : cmLabel(r.voxel),
                           fmtVal(s.miou3), fmtVal(s.miou_p3), fmtVal(s.pq3), fmtVal(s.ap50_3), fmtVal(s.ap50_3s),
                           fmtVal(s.miou2),
                           fmtVal(s.pq2), fmtVal(raw.miou2), fmtVal(raw.pq2));
    }
    return out;
}

std::string buildReport(const Plan& plan, const std::vector<RunResult>& runs, const ReportContext& ctx)
{
    std::ostringstream md;
    const std::string a = cm(plan.ablation_voxel);
    const bool spread = runs.size() > 1;
    const std::string md_dir = fs::path(ctx.markdown_path).parent_path().string();

    // ---- setup
    std::string scenes, seeds;
    for (const auto& s : plan.scenes) scenes += (scenes.empty() ? "" : ", ") + s;
    for (uint64_t s : plan.seeds) seeds += (seeds.empty() ? "" : ", ") + std::to_string(s);
    md << "## How these numbers were made\n\n";
    md << "```sh\n" << ctx.command << "\n```\n\n";
    md << "(from the repository root; after a normal build the binary is `build/bin/pndt-experiments`)\n\n";
    md << "* machine: " << ctx.machine << "\n";
    if (!ctx.revision.empty()) md << "* sources: " << ctx.revision << "\n";
    md << fmt::format("* run time: {:.0f} s ({:.1f} min) for {} runs", ctx.wall_seconds, ctx.wall_seconds / 60.0,
                      runs.size());
    double gen = 0, integ = 0, ev = 0;
    for (const RunResult& r : runs) gen += r.seconds_generate, integ += r.seconds_integrate, ev += r.seconds_eval;
    md << fmt::format(" (summed over runs: generating frames and input statistics {:.0f} s, integrating into all maps {:.0f} s, evaluating {:.0f} s)\n",
                      gen, integ, ev);
    md << fmt::format("* data: scenes {} × seeds {} = {} runs; {} frames per run at {} (seg-noise 1, depth-noise 1, "
                      "true poses); 2D evaluation on every {}th frame ({} frames per run)\n",
                      scenes, seeds, runs.size(), plan.frames, plan.resolution, plan.eval_every,
                      runs.empty() ? 0 : runs.front().eval_frames);
    md << "* benchmark: NYUv2-40 (40 classes, AP on the 37 thing classes), `pndt::eval::PanopticEvaluator`; 3D on "
          "the generated 1 cm GT cloud (each point labelled with `PanopticMap::labelAt`), 2D by rendering the final "
          "map into the evaluated frames (`PanopticMap::render`) against the GT images\n";
    md << fmt::format("* map options: the paper's {} preset (theta_L/theta_Z = 0.7/{:g}, theta_M/theta_N = 0.2/0.1, "
                      "theta_St 0.9, theta_B 0.8, theta_O 0.25, max range {:g} m) for every row unless the row says "
                      "otherwise; {}\n",
                      plan.resolution == "1024x768" ? "Hypersim" : "ScanNet", plan.resolution == "1024x768" ? 0.4 : 0.1,
                      plan.resolution == "1024x768" ? 20.0 : 10.0,
                      ctx.validation
                          ? fmt::format("our rules beyond the paper use thresholds chosen on separate validation "
                                        "scenes (split_coverage {:g}, fragment_merge_frames {:g}, "
                                        "fragment_absorb_ratio {:g}, label_fill_distance {:g} m; see \"Validation\"); "
                                        "theta_L is the paper's except in rows that say so",
                                        plan.rules.split_coverage, plan.rules.fragment_merge_frames,
                                        plan.rules.fragment_absorb_ratio, plan.rules.label_fill_distance)
                          : "nothing was tuned");
    md << "* numbers: percent, mean ± sample standard deviation over the runs (each run scored on its own)\n\n";

    // ---- Table I
    md << "## Table I: maps vs. their per-frame input\n\n";
    md << "Columns as in the paper's Table I. \"input 2D\" is the raw per-frame segmentation the map was built "
          "from, scored on the same evaluated frames. The raw input has no 3D output (it is per frame), so its 3D "
          "cells are empty: in 3D only maps are compared.\n\n";
    md << "**(a) Ground-truth segmentation as input (seg-noise 0): the representational ceiling**\n\n";
    md << tableHeader();
    md << tableRow(plan, runs, "raw-gt", spread);
    for (double v : plan.voxels) md << tableRow(plan, runs, "ndt-gt@" + cm(v), spread);
    md << "\n**(b) Network-like segmentation as input (seg-noise 1)**\n\n";
    md << tableHeader();
    md << tableRow(plan, runs, "raw-net", spread);
    for (double v : plan.voxels) md << tableRow(plan, runs, "ndt-net@" + cm(v), spread);
    for (double v : plan.voxels) md << tableRow(plan, runs, "paper-net@" + cm(v), spread);
    for (double v : plan.voxels) md << tableRow(plan, runs, "cube-net@" + cm(v), spread);
    for (double v : plan.voxels) md << tableRow(plan, runs, "tuned-net@" + cm(v), spread);
    md << "\n\"PanopticNDT\" is our map (our rules beyond the paper on, at the thresholds chosen on the validation "
          "scenes); \"paper preset (exact)\" is every rule as the paper states it (`config/presets/paper.ini`, "
          "`MapOptions::applyPaperRules`: per-pixel rays each applying its miss, Eq. 9 over every top voxel, a "
          "dense h^L with a void bin, no wiping of freed voxels, none of our five rules).\n";
    md << "\n**(c) Ablations (network-like input)**\n\n";
    md << tableHeader();
    md << tableRow(plan, runs, "raw-net", spread);
    md << tableRow(plan, runs, "ndt-net@" + a, spread, "PanopticNDT (reference)");
    md << tableRow(plan, runs, "cube-net@" + a, spread);
    for (double v : plan.voxels) md << tableRow(plan, runs, "noprop-net@" + cm(v), spread);
    if (std::find(plan.voxels.begin(), plan.voxels.end(), plan.ablation_voxel) == plan.voxels.end())
        md << tableRow(plan, runs, "noprop-net@" + a, spread);
    md << tableRow(plan, runs, "semonly-net@" + a, spread);
    md << tableRow(plan, runs, "thr-0.1-0.05@" + a, spread);
    md << tableRow(plan, runs, "thr-0.3-0.15@" + a, spread);
    md << tableRow(plan, runs, "paper-instances@" + a, spread);
    md << tableRow(plan, runs, "nofill-net@" + a, spread);
    md << tableRow(plan, runs, "perpixel-net@" + a, spread);
    md << "\n";
    md << "* **w/o NDT**: `use_ndt = false` (cube voxels: plain free-space updates, containing-voxel lookup).\n"
          "* **w/o panoptic propagation**: the same map as PanopticNDT, read without propagation: each voxel / "
          "pixel takes <argmax h^L, the voxel's own top instance if that class is a thing class, else 0> instead "
          "of <the instance's majority class, instance>. Where the voxel is no panoptic thing (pthing fails), the "
          "instance is 0 in both readouts.\n"
          "* **semantic only**: the map is fed the frames without instance images (no matching, no instance "
          "histograms); its panoptic output is <argmax h^L, 0>, i.e. PQ scores one segment per class and scene "
          "(3D) or image (2D), and AP is 0 since it has no instances.\n"
          "* **theta_M/theta_N**: the matching thresholds (default 0.2/0.1).\n"
          "* **the paper's instance rules**: `class_consistent_instances = false`, `split_coverage = 0`, "
          "`fragment_merge_frames = 0`, `fragment_absorb_ratio = 0` (doc/design-decisions.md, \"Instances keep one "
          "class\"): a prediction may match a map instance of another class and always takes one id, and fragments "
          "heal only through the histograms.\n"
          "* **w/o label fill**: `label_fill_distance = 0`: occupied voxels that never had a view above theta_L "
          "stay void in the panoptic output instead of taking their labelled neighbours' label (the semantic "
          "output, and so mIoU, never uses the fill).\n"
          "* **per-pixel rays**: `ray_mode = per_pixel`: a free-space ray to every mapped pixel's sample "
          "instead of one ray per distinct endpoint voxel to the mean of its samples (the default, the speed-up's "
          "one approximation; doc/benchmarks.md).\n\n";

    // ---- validation
    if (ctx.validation)
    {
        const ValidationResult& v = *ctx.validation;
        std::string vs, vseeds;
        for (const auto& x : v.plan.scenes) vs += (vs.empty() ? "" : ", ") + x;
        for (uint64_t x : v.plan.seeds) vseeds += (vseeds.empty() ? "" : ", ") + std::to_string(x);
        md << "## Validation: thresholds chosen on separate scenes\n\n";
        md << fmt::format(
            "Scenes {} (seeds {}; never used in the tables above or below), {} frames, "
            "PanopticNDT at {} with network-like input. One parameter is varied at a time, every other at its "
            "default (theta_L the paper's 0.7; our rules' thresholds the shipped defaults, which an earlier run of "
            "this validation chose). Criterion: the mean of 3D mIoU, 3D PQ, 2D mIoU and 2D PQ over the {} "
            "validation runs; the best value per parameter is chosen if it beats the default's criterion by more "
            "than {:g} points, else the default. Chosen: **theta_L = {:g}**{}; our rules: split_coverage = {:g}, "
            "fragment_merge_frames = {:g}, fragment_absorb_ratio = {:g}, label_fill_distance = {:g} m (used by "
            "every map row above).\n\n",
            vs, vseeds, v.plan.frames, cmLabel(v.plan.ablation_voxel), v.runs.size(), kValidationTieMargin,
            v.chosen,
            v.chosen == 0.7 ? " (the paper's default; no tuned rows are added)"
                            : " (rows \"tuned on validation scenes\" in table (b); the paper's 0.7 stays the reference)",
            v.rules.split_coverage, v.rules.fragment_merge_frames, v.rules.fragment_absorb_ratio,
            v.rules.label_fill_distance);
        md << "| parameter = value | 3D mIoU | 3D PQ | 2D mIoU | 2D PQ | 3D labelled | 3D correct / labelled | criterion |\n"
              "|---|---|---|---|---|---|---|---|\n";
        md << fmt::format("| raw input | – | – | {} | {} | – | – | – |\n",
                          fmtStat(stat(values(v.runs, "raw-net", &Scores::miou2)), false),
                          fmtStat(stat(values(v.runs, "raw-net", &Scores::pq2)), false));
        for (const auto& [param, list] : v.sweep)
        {
            const double chosen = param == "theta_l" ? v.chosen : v.rules.get(param);
            for (double t : list)
            {
                const std::string id = validationRowId(param, t);
                auto c = [&](Field f) { return fmtStat(stat(values(v.runs, id, f)), false); };
                const std::string name = fmt::format("{} = {:g}{}", param, t, t == defaultValue(param) ? " (default)" : "");
                md << fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", t == chosen ? "**" + name + "**" : name,
                                  c(&Scores::miou3), c(&Scores::pq3), c(&Scores::miou2), c(&Scores::pq2),
                                  c(&Scores::coverage3), c(&Scores::precision3),
                                  fmtVal(validationCriterion(v, param, t)));
            }
        }
        md << "\n";
    }

    // ---- per run
    md << fmt::format("## Per run ({}; map = PanopticNDT, network-like input)\n\n", cmLabel(plan.ablation_voxel));
    md << "| scene | seed | GT points | raw 2D mIoU | map 2D mIoU | Δ | raw 2D PQ | map 2D PQ | Δ | map 3D mIoU | "
          "map 3D PQ | w/o NDT 3D mIoU | w/o NDT 3D PQ | GT-input map 3D PQ |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const RunResult& r : runs)
    {
        auto get = [&](const std::string& id) {
            auto it = r.scores.find(id);
            return it == r.scores.end() ? Scores{} : it->second;
        };
        const Scores raw = get("raw-net"), map = get("ndt-net@" + a), cube = get("cube-net@" + a),
                     gtm = get("ndt-gt@" + a);
        md << fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r.scene, r.seed,
                          r.gt_points, fmtVal(raw.miou2), fmtVal(map.miou2), fmtDelta(map.miou2 - raw.miou2),
                          fmtVal(raw.pq2), fmtVal(map.pq2), fmtDelta(map.pq2 - raw.pq2), fmtVal(map.miou3),
                          fmtVal(map.pq3), fmtVal(cube.miou3), fmtVal(cube.pq3), fmtVal(gtm.pq3));
    }
    md << "\n";

    // ---- diagnostics
    md << "## Diagnostics: which errors survive integration\n\n";
    md << "What happened to every ground-truth thing segment (≥ 100 pixels / points), summed over all runs "
          "(2D: all evaluated frames; 3D: the GT clouds). *matched*: a same-class segment with IoU > 0.5 (a PQ "
          "TP); *missed*: mostly void or stuff; *wrong class*: mostly another thing class; *split*: right class "
          "but the best same-class segment covers < 50 % of it; *oversized*: right class, covered ≥ 50 %, but the "
          "predicted segment spans more (merged with neighbours or bled); *fragments / GT*: predicted thing "
          "segments covering ≥ 10 % of a GT segment, on average; *false pos.*: share of predicted thing "
          "segments (≥ 100 elements) that match nothing and lie mostly on non-void GT; *FP causes*: the GT "
          "segment a false positive overlaps most is stuff / a thing of another class / a same-class thing that "
          "another segment matches / a same-class thing nothing matches (shares of the false positives).\n\n";
    md << "**2D (same frames for all rows)**\n\n" << segHeader();
    md << segRow("raw network-like input", sumSeg(runs, "raw-net", false));
    md << segRow("PanopticNDT " + cmLabel(plan.ablation_voxel), sumSeg(runs, "ndt-net@" + a, false));
    if (findRow(plan, "tuned-net@" + a))
        md << segRow(fmt::format("PanopticNDT, theta_L = {:g}, {}", plan.tuned_theta_l, cmLabel(plan.ablation_voxel)),
                     sumSeg(runs, "tuned-net@" + a, false));
    md << segRow("w/o NDT " + cmLabel(plan.ablation_voxel), sumSeg(runs, "cube-net@" + a, false));
    md << segRow("w/o propagation " + cmLabel(plan.ablation_voxel), sumSeg(runs, "noprop-net@" + a, false));
    md << segRow("raw GT input", sumSeg(runs, "raw-gt", false));
    md << segRow("PanopticNDT, GT input " + cmLabel(plan.ablation_voxel), sumSeg(runs, "ndt-gt@" + a, false));
    md << "\n**3D (GT clouds)**\n\n" << segHeader();
    for (double v : plan.voxels) md << segRow("PanopticNDT " + cmLabel(v), sumSeg(runs, "ndt-net@" + cm(v), true));
    if (findRow(plan, "tuned-net@" + a))
        md << segRow(fmt::format("PanopticNDT, theta_L = {:g}, {}", plan.tuned_theta_l, cmLabel(plan.ablation_voxel)),
                     sumSeg(runs, "tuned-net@" + a, true));
    md << segRow("w/o NDT " + cmLabel(plan.ablation_voxel), sumSeg(runs, "cube-net@" + a, true));
    md << segRow("w/o propagation " + cmLabel(plan.ablation_voxel), sumSeg(runs, "noprop-net@" + a, true));
    for (double v : plan.voxels)
        md << segRow("PanopticNDT, GT input " + cmLabel(v), sumSeg(runs, "ndt-gt@" + cm(v), true));
    md << "\n";
    {
        size_t gt_inst = 0, net_inst = 0, gt_map_inst = 0;
        for (const RunResult& r : runs)
        {
            gt_inst += r.gt_instances3;
            auto it = r.map_instances.find("ndt-net@" + a);
            if (it != r.map_instances.end()) net_inst += it->second;
            it = r.map_instances.find("ndt-gt@" + a);
            if (it != r.map_instances.end()) gt_map_inst += it->second;
        }
        md << fmt::format("Instances ({}, summed over runs): {} GT thing instances with ≥ 100 points in the GT "
                          "clouds; the maps hold {} instances (network-like input) and {} (GT input), counted by "
                          "`PanopticMap::instances()` (all sizes).\n\n",
                          cmLabel(plan.ablation_voxel), gt_inst, net_inst, gt_map_inst);
        md << "Semantic coverage and accuracy (mean over runs): *labelled* = share of the non-void GT that gets "
              "any class (a map voxel without semantic update, or a pixel / point the map does not reach, is "
              "void); *correct* = share with the right class (argmax h^L); *correct / labelled* = the same among "
              "the labelled ones.\n\n"
              "| labelling | 3D labelled | 3D correct | 3D correct / labelled | 2D labelled | 2D correct | 2D "
              "correct / labelled |\n|---|---|---|---|---|---|---|\n";
        std::vector<std::string> ids{"raw-net"};
        for (double v : plan.voxels) ids.push_back("ndt-net@" + cm(v));
        for (double v : plan.voxels) ids.push_back("tuned-net@" + cm(v));
        ids.push_back("cube-net@" + a);
        ids.push_back("raw-gt");
        for (double v : plan.voxels) ids.push_back("ndt-gt@" + cm(v));
        for (const std::string& id : ids)
        {
            const RowSpec* r = findRow(plan, id);
            if (!r) continue;
            auto c = [&](Field f) { return fmtStat(stat(values(runs, id, f)), false); };
            md << fmt::format("| {}{}{} | {} | {} | {} | {} | {} | {} |\n", r->group == "gt" ? "GT input: " : "",
                              r->raw ? "raw input" : r->label, r->raw ? "" : " " + cmLabel(r->voxel),
                              c(&Scores::coverage3), c(&Scores::accuracy3), c(&Scores::precision3),
                              c(&Scores::coverage2), c(&Scores::accuracy2), c(&Scores::precision2));
        }
        md << "\n";
        InputStats in;
        for (const RunResult& r : runs) in += r.input;
        auto pc = [](uint64_t x, uint64_t y) { return y ? 100.0 * double(x) / double(y) : kNaN; };
        md << fmt::format(
            "The network-like input of all {} frames (pixels with benchmark GT): {:.1f} % pass the map's semantic "
            "score filter S^L > theta_L = 0.7 and update h^L; {:.1f} % of the passing pixels have the right class, "
            "but only {:.1f} % of the filtered ones (overall raw pixel accuracy {:.1f} %). Of the GT thing pixels, "
            "{:.1f} % are predicted as a thing instance with S^P > theta_Z and can update h^Z.\n",
            runs.empty() ? 0 : runs.front().frames * runs.size(), pc(in.pass, in.pixels),
            pc(in.pass_correct, in.pass), pc(in.fail_correct, in.pixels - in.pass),
            pc(in.pass_correct + in.fail_correct, in.pixels), pc(in.thing_pass, in.thing_pixels));
        md << fmt::format(
            "The filter drops {:.1f} % of the right-class pixels. Of those, {:.1f} % belong to a GT object the "
            "generator split (over-segmented) in that frame, {:.1f} % to one it merged with a neighbour, {:.1f} % to "
            "other things, {:.1f} % are stuff. The generator lowers S^L of a right-class pixel only near a segment "
            "boundary and on difficult objects; splitting or merging an object lowers its instance score S^P, not "
            "S^L.\n",
            pc(in.fail_correct, in.pass_correct + in.fail_correct), pc(in.dropped_split, in.fail_correct),
            pc(in.dropped_merged, in.fail_correct), pc(in.dropped_other_thing, in.fail_correct),
            pc(in.dropped_stuff, in.fail_correct));
        md << "\n";
    }

    // ---- integration as a per-object vote
    {
        struct Bin
        {
            size_t objects = 0;
            double views = 0, views_right = 0, views_usable = 0, raw_acc = 0;
            double lab[2] = {0, 0}, acc[2] = {0, 0};
        };
        const double edges[] = {0.0, 0.25, 0.5, 0.75, 1.0001};
        Bin bins[4];
        const std::string ids[2] = {"ndt-net@" + a, "tuned-net@" + a};
        const bool has_tuned = findRow(plan, ids[1]) != nullptr;
        for (const RunResult& r : runs)
            for (const auto& [label, o] : r.objects)
            {
                auto it0 = r.object_points.find(ids[0]);
                if (it0 == r.object_points.end()) continue;
                auto p0 = it0->second.find(label);
                if (p0 == it0->second.end() || p0->second.points < 100 || o.views == 0) continue;
                const double share = double(o.views_right) / double(o.views);
                int b = 0;
                while (b < 3 && share >= edges[b + 1]) ++b;
                Bin& bin = bins[b];
                ++bin.objects;
                bin.views += o.views;
                bin.views_right += share;
                bin.views_usable += double(o.views_usable) / double(o.views);
                bin.raw_acc += double(o.correct) / double(o.pixels);
                for (int m = 0; m < 2; ++m)
                {
                    auto it = r.object_points.find(ids[m]);
                    if (it == r.object_points.end()) continue;
                    auto pp = it->second.find(label);
                    if (pp == it->second.end()) continue;
                    bin.lab[m] += double(pp->second.labelled) / double(pp->second.points);
                    bin.acc[m] += double(pp->second.correct) / double(pp->second.points);
                }
            }
        md << "## Integration as a per-object vote\n\n";
        md << fmt::format(
            "GT thing instances (≥ 100 GT points) grouped by how often the raw input gets them right: the share "
            "of the frames that see them (≥ 100 pixels) in which most of their pixels have the right class. "
            "*views usable*: frames in which most of their pixels have the right class and S^L > theta_L = 0.7, "
            "i.e. can vote for the right class in the default map. *raw pixel acc.*: share of their pixels with the right class over those frames. *map*: share of "
            "their GT points the map ({}) labels at all / labels with the right class (argmax h^L). Means over "
            "objects, all runs.\n\n",
            cmLabel(plan.ablation_voxel));
        md << "| views right | objects | views per object | views right (mean) | views usable (mean) | raw pixel acc. "
              "| map labelled | map correct |"
           << (has_tuned ? fmt::format(" map theta_L = {:g} labelled | map theta_L = {:g} correct |", plan.tuned_theta_l,
                                       plan.tuned_theta_l)
                         : std::string())
           << "\n|---|---|---|---|---|---|---|---|" << (has_tuned ? "---|---|" : "") << "\n";
        const char* names[] = {"< 25 %", "25–50 %", "50–75 %", "≥ 75 %"};
        for (int b = 0; b < 4; ++b)
        {
            const Bin& bin = bins[b];
            const double n = double(std::max<size_t>(1, bin.objects));
            md << fmt::format("| {} | {} | {:.1f} | {:.1f} % | {:.1f} % | {:.1f} % | {:.1f} % | {:.1f} % |", names[b],
                              bin.objects, bin.views / n, 100 * bin.views_right / n, 100 * bin.views_usable / n,
                              100 * bin.raw_acc / n, 100 * bin.lab[0] / n, 100 * bin.acc[0] / n);
            if (has_tuned) md << fmt::format(" {:.1f} % | {:.1f} % |", 100 * bin.lab[1] / n, 100 * bin.acc[1] / n);
            md << "\n";
        }
        md << "\n";
    }

    // ---- per class (pooled)
    const eval::Benchmark bench = eval::Benchmark::nyuv2_40();
    std::map<std::string, eval::PanopticEvaluator> pooled;
    for (const std::string& k : pooledKeys(plan)) pooled.emplace(k, eval::PanopticEvaluator(bench));
    for (const RunResult& r : runs)
        for (const auto& item : r.pooled) pooled.at(item.key).add(*item.gt, item.pred);
    std::map<std::string, eval::ClassTable> tables;
    for (auto& [k, ev] : pooled) tables[k] = eval::perClassTable(ev.result(), bench, k);
    const std::string k_raw = "raw-net/2d", k_map2 = "ndt-net@" + a + "/2d", k_map3 = "ndt-net@" + a + "/3d",
                      k_cube3 = "cube-net@" + a + "/3d", k_gt3 = "ndt-gt@" + a + "/3d",
                      k_gt2 = "ndt-gt@" + a + "/2d";
    md << fmt::format("## Per class (pooled over all runs; maps at {})\n\n", cmLabel(plan.ablation_voxel));
    md << "Pooled: one evaluator over all runs' frames / clouds (so the means differ slightly from the mean of "
          "per-run scores above). Classes without ground truth are left out. Things: AP50 (3D).\n\n";
    md << "| class | raw 2D IoU | map 2D IoU | GT-input map 2D IoU | map 3D IoU | w/o NDT 3D IoU | raw 2D PQ | "
          "map 2D PQ | map 3D PQ | w/o NDT 3D PQ | GT-input map 3D PQ | map 3D AP50 |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    auto pv = [&](const std::string& k, uint16_t id, const char* col) { return 100.0 * tables.at(k).value(id, col); };
    for (const auto& row : tables.at(k_raw).rows)
    {
        const bool any = !std::isnan(pv(k_raw, row.id, "PQ")) || !std::isnan(pv(k_map3, row.id, "PQ"));
        if (!any) continue;
        md << fmt::format("| {}{} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", row.name,
                          row.is_thing ? "" : " (stuff)", fmtVal(pv(k_raw, row.id, "IoU")), fmtVal(pv(k_map2, row.id, "IoU")),
                          fmtVal(pv(k_gt2, row.id, "IoU")),
                          fmtVal(pv(k_map3, row.id, "IoU")), fmtVal(pv(k_cube3, row.id, "IoU")),
                          fmtVal(pv(k_raw, row.id, "PQ")), fmtVal(pv(k_map2, row.id, "PQ")),
                          fmtVal(pv(k_map3, row.id, "PQ")), fmtVal(pv(k_cube3, row.id, "PQ")),
                          fmtVal(pv(k_gt3, row.id, "PQ")), fmtVal(pv(k_map3, row.id, "AP50")));
    }
    auto summary = [&](const std::string& k, size_t i, const char* col) {
        const auto& t = tables.at(k);
        const int c = t.columnIndex(col);
        return c < 0 || i >= t.summary.size() ? kNaN : 100.0 * t.summary[i].values[size_t(c)];
    };
    md << fmt::format("| **mean** | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n\n",
                      fmtVal(summary(k_raw, 0, "IoU")), fmtVal(summary(k_map2, 0, "IoU")), fmtVal(summary(k_gt2, 0, "IoU")),
                      fmtVal(summary(k_map3, 0, "IoU")), fmtVal(summary(k_cube3, 0, "IoU")),
                      fmtVal(summary(k_raw, 0, "PQ")), fmtVal(summary(k_map2, 0, "PQ")),
                      fmtVal(summary(k_map3, 0, "PQ")), fmtVal(summary(k_cube3, 0, "PQ")),
                      fmtVal(summary(k_gt3, 0, "PQ")), fmtVal(summary(k_map3, 0, "AP50")));
    md << fmt::format("Things / stuff PQ: raw 2D {} / {}, map 2D {} / {}, map 3D {} / {}.\n\n",
                      fmtVal(summary(k_raw, 1, "PQ")), fmtVal(summary(k_raw, 2, "PQ")), fmtVal(summary(k_map2, 1, "PQ")),
                      fmtVal(summary(k_map2, 2, "PQ")), fmtVal(summary(k_map3, 1, "PQ")),
                      fmtVal(summary(k_map3, 2, "PQ")));

    // ---- charts (paper Fig. 3 style)
    fs::create_directories(ctx.images_dir);
    auto chart = [&](const std::string& column, const std::string& file, const std::string& title)
    {
        eval::ClassTable t = eval::compareColumn({{"raw input 2D", tables.at(k_raw)},
                                                  {"map 2D", tables.at(k_map2)},
                                                  {"map 3D", tables.at(k_map3)},
                                                  {"map 3D, GT input", tables.at(k_gt3)}},
                                                 column, title);
        t.rows.erase(std::remove_if(t.rows.begin(), t.rows.end(),
                                    [](const eval::ClassTable::Row& r) {
                                        return std::all_of(r.values.begin(), r.values.end(),
                                                           [](double v) { return std::isnan(v); });
                                    }),
                     t.rows.end());
        t.summary.erase(std::remove_if(t.summary.begin(), t.summary.end(),
                                       [](const eval::ClassTable::Row& r) { return r.name != "mean"; }),
                        t.summary.end());
        eval::BarChartOptions o;
        o.show_values = false;
        o.plot_height = 260;
        o.bar_width = 7;
        o.group_gap = 8;
        const std::string path = (fs::path(ctx.images_dir) / file).string();
        eval::writeBarChartPng(path, t, o);
        return path;
    };
    const std::string pq_png =
        chart("PQ", ctx.image_prefix + "per_class_pq.png",
              fmt::format("Per-class PQ (NYUv2-40, {} runs pooled, {} maps)", runs.size(), cmLabel(plan.ablation_voxel)));
    const std::string iou_png =
        chart("IoU", ctx.image_prefix + "per_class_iou.png",
              fmt::format("Per-class IoU (NYUv2-40, {} runs pooled, {} maps)", runs.size(), cmLabel(plan.ablation_voxel)));
    md << "![per-class PQ](" << shortPath(md_dir, pq_png) << ")\n\n";
    md << "![per-class IoU](" << shortPath(md_dir, iou_png) << ")\n";
    return md.str();
}

void writeReport(const std::string& path, const std::string& generated)
{
    std::string before, after;
    {
        std::ifstream in(path);
        if (in)
        {
            std::stringstream ss;
            ss << in.rdbuf();
            const std::string old = ss.str();
            const size_t b = old.find(kBegin), e = old.find(kEnd);
            if (b != std::string::npos && e != std::string::npos && e > b)
            {
                before = old.substr(0, b);
                after = old.substr(e + std::string(kEnd).size());
            }
            else
                throw std::runtime_error(path + ": exists but has no pndt-experiments markers; not overwriting it");
        }
        else
        {
            before = "# Experiments: PanopticNDT on the synthetic benchmark\n\n";
            after = "\n\n## Discussion\n\n(not written yet)\n";
        }
    }
    const fs::path p(path);
    if (p.has_parent_path()) fs::create_directories(p.parent_path());
    const fs::path tmp = p.string() + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out << before << kBegin << "\n" << generated << kEnd << after;
        out.flush();
        if (!out) throw std::runtime_error(tmp.string() + ": write failed");
    }
    fs::rename(tmp, p);
}

}  // namespace pndt::exp
