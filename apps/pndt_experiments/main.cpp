// pndt-experiments: one command that runs the paper-style experiments on the synthetic
// benchmark (issue 5) and writes doc/results.md (Table I-shaped tables, per-run rows,
// diagnostics, per-class results) and per-class bar charts (paper Fig. 3 style).
//
//   build/bin/pndt-experiments            # full run: 3 scenes x 3 seeds, 5/10/20 cm (+ validation)
//   build/bin/pndt-experiments --quick    # minimal run (one scene, 10 cm) in a few minutes
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <pndt/app/cli_numbers.h>
#include <pndt/sim/indoor_scene.h>
#include <sys/utsname.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "experiment.h"
#include "report.h"

using namespace pndt;

namespace
{
std::string readLineWith(const std::string& file, const std::string& key)
{
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(key, 0) == 0) return line;
    return {};
}

std::string machineDescription()
{
    std::string cpu = readLineWith("/proc/cpuinfo", "model name");
    if (auto p = cpu.find(':'); p != std::string::npos) cpu = cpu.substr(p + 2);
    std::string os = readLineWith("/etc/os-release", "PRETTY_NAME=");
    if (!os.empty()) os = os.substr(12);
    os.erase(std::remove(os.begin(), os.end(), '"'), os.end());
    std::string mem = readLineWith("/proc/meminfo", "MemTotal:");
    double gb = 0;
    if (!mem.empty()) gb = std::atof(mem.substr(9).c_str()) / 1024.0 / 1024.0;
    utsname u{};
    uname(&u);
    return fmt::format("{}, {} hardware threads (shared with other work), {:.0f} GB RAM; {} (Linux {} {})",
                       cpu.empty() ? "unknown CPU" : cpu, std::thread::hardware_concurrency(), gb,
                       os.empty() ? "unknown OS" : os, u.release, u.machine);
}

std::string runCommand(const std::string& cmd)
{
    std::string out;
    if (FILE* p = popen(cmd.c_str(), "r"))
    {
        char buf[256];
        while (fgets(buf, sizeof buf, p)) out += buf;
        pclose(p);
    }
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    return out;
}

std::string sourceRevision()
{
#ifdef PNDT_SOURCE_DIR
    const std::string dir = PNDT_SOURCE_DIR;
    const std::string head = runCommand("git -C '" + dir + "' rev-parse --short HEAD 2>/dev/null");
    if (head.empty()) return {};
    const std::string dirty = runCommand("git -C '" + dir + "' status --porcelain --untracked-files=no 2>/dev/null");
    return "git " + head + (dirty.empty() ? "" : " with uncommitted changes in the working tree");
#else
    return {};
#endif
}

template <typename T>
std::vector<T> parseList(const std::string& s, const char* what)
{
    std::vector<T> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
    {
        if (item.empty()) continue;
        std::stringstream is(item);
        T v{};
        is >> v;
        if (is.fail() || !is.eof()) throw std::invalid_argument(std::string("bad ") + what + " '" + item + "'");
        out.push_back(v);
    }
    if (out.empty()) throw std::invalid_argument(std::string("empty ") + what + " list");
    return out;
}
/// Runs every (scene, seed) of the plan with plan.jobs workers; results in plan order.
std::vector<exp::RunResult> runAll(const exp::Plan& plan, const std::string& what)
{
    struct Job
    {
        std::string scene;
        uint64_t seed;
    };
    std::vector<Job> jobs;
    for (const auto& s : plan.scenes)
        for (uint64_t seed : plan.seeds) jobs.push_back({s, seed});
    std::vector<exp::RunResult> runs(jobs.size());
    std::vector<std::exception_ptr> errors(jobs.size());
    std::atomic<size_t> next{0};
    std::mutex print_mutex;
    auto worker = [&]()
    {
        for (size_t k = next++; k < jobs.size(); k = next++)
        {
            try
            {
                runs[k] = exp::runExperiment(plan, jobs[k].scene, jobs[k].seed);
                const exp::RunResult& r = runs[k];
                std::lock_guard<std::mutex> lock(print_mutex);
                fmt::print("{} run {}/{}: {} seed {} ({} frames, {} GT points, {} evaluated frames) in {:.0f} s "
                           "(generate {:.0f} s, integrate {:.0f} s, evaluate {:.0f} s)\n{}",
                           what, k + 1, jobs.size(), r.scene, r.seed, r.frames, r.gt_points, r.eval_frames,
                           r.seconds, r.seconds_generate, r.seconds_integrate, r.seconds_eval,
                           exp::summaryLines(plan, r));
                if (plan.details)
                {
                    const eval::Benchmark b = eval::Benchmark::nyuv2_40();
                    fmt::print("    3D GT thing segments (class:instance, points, outcome, dominant predicted "
                               "class and share, void, stuff, best same-class IoU / cover, fragments):\n");
                    for (const exp::SegmentDetail& d : r.details3)
                    {
                        auto it = r.objects.find(d.gt);
                        const exp::ObjectViews o = it == r.objects.end() ? exp::ObjectViews{} : it->second;
                        fmt::print("      {:>14}:{:<4} {:>7} {:<11} {:>14} {:4.2f} void {:4.2f} stuff {:4.2f} "
                                   "IoU {:4.2f} cover {:4.2f} frag {} | raw: right in {}/{} views, pixel acc. {:.2f}, "
                                   "usable in {} views\n",
                                   b.className(d.gt >> 16), d.gt & 0xFFFF, d.size, d.outcome, b.className(d.dominant),
                                   d.dominant_share, d.void_share, d.stuff_share, d.best_iou, d.best_cover,
                                   d.fragments, o.views_right, o.views, o.pixels ? double(o.correct) / o.pixels : 0.0,
                                   o.views_usable);
                    }
                }
                std::fflush(stdout);
            }
            catch (...)
            {
                errors[k] = std::current_exception();
            }
        }
    };
    std::vector<std::thread> threads;
    const int n_threads = std::min<int>(plan.jobs, int(jobs.size()));
    for (int t = 1; t < n_threads; ++t) threads.emplace_back(worker);
    worker();
    for (auto& t : threads) t.join();
    for (auto& e : errors)
        if (e) std::rethrow_exception(e);
    return runs;
}
}  // namespace

int main(int argc, char** argv)
{
    exp::Plan plan;
    std::string scenes = "held_living,held_office,held_bedroom", seeds = "1,2,3", voxels = "0.05,0.1,0.2";
    std::string out_md = "doc/results.md", images = "doc/images";
    bool quick = false;
    // Validation rooms of every type the tables report (living, office, bedroom) and dining, from
    // other layouts and seeds than the held_* rooms.
    std::string val_scenes = "bedroom,dining,living,office", val_seeds = "1,2", sweep = "0.3,0.5,0.7,0.9";
    // Each sweep reaches past the values an earlier validation chose, so a choice at its edge shows;
    // fragment_absorb_ratio stops at 0.35 (beyond 1 : 3, touching objects of one class are common).
    std::vector<std::string> rule_sweeps = {"split_coverage=0.3/0.5/0.7/0.9", "fragment_merge_frames=3/5/8/12",
                                            "fragment_absorb_ratio=0.1/0.15/0.25/0.35",
                                            "label_fill_distance=0.1/0.2/0.3/0.5"};
    plan.frames = 60;

    CLI::App app{"pndt-experiments: the paper's Table I experiments on the synthetic benchmark; writes "
                 "doc/results.md and per-class bar charts"};
    app.add_flag("--quick", quick,
                 "minimal run: scene held_living, seed 1, 30 frames, 10 cm only, validation on bedroom seed 1; writes "
                 "out/experiments-quick/ unless --out / --images are given");
    app.add_option("--scenes", scenes, "comma-separated scene presets or numbers")->capture_default_str();
    app.add_option("--seeds", seeds, "comma-separated recording seeds")->capture_default_str();
    app.add_option("-n,--frames", plan.frames, "frames per run")->capture_default_str()->check(CLI::Range(1, 100000));
    app.add_option("--resolution", plan.resolution, "640x480 (ScanNet-like) or 1024x768 (Hypersim-like)")
        ->capture_default_str()
        ->check(CLI::IsMember({"640x480", "1024x768"}));
    app.add_option("--voxels", voxels, "voxel sizes in metres for the main rows")->capture_default_str();
    app.add_option("--ablation-voxel", plan.ablation_voxel, "voxel size of the ablations and per-class tables")
        ->capture_default_str()
        ->check(app::kPositive);
    app.add_option("--eval-every", plan.eval_every, "2D: evaluate every k-th frame (0, k, 2k, ...)")
        ->capture_default_str()
        ->check(CLI::Range(1, 100000));
    app.add_option("-j,--jobs", plan.jobs, "runs in parallel (each run is single-threaded)")
        ->capture_default_str()
        ->check(CLI::Range(1, 64));
    app.add_option("-o,--out", out_md, "Markdown report (text outside the generated block is kept)")
        ->capture_default_str();
    app.add_option("--images", images, "folder of the bar-chart PNGs")->capture_default_str();
    app.add_option("--validation-scenes", val_scenes,
                   "scenes for tuning theta_L (never the reported ones; empty = no tuning)")
        ->capture_default_str();
    app.add_option("--validation-seeds", val_seeds, "seeds of the validation scenes")->capture_default_str();
    app.add_option("--sweep-theta-l", sweep, "theta_L values tried on the validation scenes")->capture_default_str();
    app.add_option("--sweep-rule", rule_sweeps,
                   "NAME=V1/V2/..: values of one of our rules' thresholds tried on the validation scenes "
                   "(repeatable; one parameter varied at a time)")
        ->capture_default_str();
    app.add_flag("-v,--verbose", plan.verbose, "progress every 10 frames");
    app.add_flag("--details", plan.details,
                 "print the outcome of every GT thing segment in 3D (PanopticNDT at the ablation voxel size)");
    CLI11_PARSE(app, argc, argv);

    const exp::ValidationResult* ctx_validation = nullptr;
    try
    {
        if (quick)
        {
            if (!app.count("--scenes")) scenes = "held_living";
            if (!app.count("--seeds")) seeds = "1";
            if (!app.count("--frames")) plan.frames = 30;
            if (!app.count("--voxels")) voxels = "0.1";
            if (!app.count("--out")) out_md = "out/experiments-quick/results.md";
            if (!app.count("--images")) images = "out/experiments-quick";
            if (!app.count("--validation-scenes")) val_scenes = "bedroom";
            if (!app.count("--validation-seeds")) val_seeds = "1";
        }
        plan.scenes = parseList<std::string>(scenes, "scene");
        plan.seeds = parseList<uint64_t>(seeds, "seed");
        plan.voxels = parseList<double>(voxels, "voxel size");
        for (double v : plan.voxels)
            if (!(v > 0)) throw std::invalid_argument("voxel sizes must be positive");

        std::string command = "pndt-experiments";
        for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
        fmt::print("pndt-experiments: {} scene(s) x {} seed(s), {} frames at {}, voxels {}, ablations at {} m, "
                   "2D every {}th frame, {} job(s)\n",
                   plan.scenes.size(), plan.seeds.size(), plan.frames, plan.resolution, voxels, plan.ablation_voxel,
                   plan.eval_every, plan.jobs);
        std::fflush(stdout);

        const auto t0 = std::chrono::steady_clock::now();
        exp::ValidationResult validation;
        if (!val_scenes.empty())
        {
            exp::Plan vplan = plan;
            vplan.scenes = parseList<std::string>(val_scenes, "validation scene");
            vplan.seeds = parseList<uint64_t>(val_seeds, "validation seed");
            for (const auto& v : vplan.scenes)
                if (std::find(plan.scenes.begin(), plan.scenes.end(), v) != plan.scenes.end())
                    throw std::invalid_argument("validation scene '" + v + "' is also a reported scene");
            vplan.details = false;
            validation.sweep["theta_l"] = parseList<double>(sweep, "theta_L value");
            for (const std::string& r : rule_sweeps)
            {
                const auto eq = r.find('=');
                const std::string name = r.substr(0, eq);
                const auto& names = exp::RuleThresholds::names();
                if (eq == std::string::npos || std::find(names.begin(), names.end(), name) == names.end())
                    throw std::invalid_argument("--sweep-rule '" + r + "': not NAME=V1/V2/.. with a rule threshold");
                std::string values = r.substr(eq + 1);
                std::replace(values.begin(), values.end(), '/', ',');
                validation.sweep[name] = parseList<double>(values, "rule threshold value");
            }
            vplan.rows = exp::makeValidationRows(vplan, validation.sweep);
            fmt::print("validation: theta_L in {{{}}} and {} rule sweeps on {} x seeds {} ({} frames, {} at {} m, {} "
                       "maps per run)\n",
                       sweep, rule_sweeps.size(), val_scenes, val_seeds, vplan.frames, plan.resolution,
                       plan.ablation_voxel, vplan.rows.size() - 1);
            std::fflush(stdout);
            validation.runs = runAll(vplan, "validation");
            validation.plan = vplan;
            validation.chosen = exp::chooseThetaL(validation);
            fmt::print("validation: chose theta_L = {:g}\n", validation.chosen);
            if (validation.chosen != 0.7) plan.tuned_theta_l = validation.chosen;
            for (const std::string& name : exp::RuleThresholds::names())
            {
                plan.rules.set(name, exp::chooseValue(validation, name));
                fmt::print("validation: chose {} = {:g}\n", name, plan.rules.get(name));
            }
            validation.rules = plan.rules;
        }
        plan.rows = exp::makeRows(plan);
        const std::vector<exp::RunResult> runs = runAll(plan, "test");
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (!validation.runs.empty()) ctx_validation = &validation;

        exp::ReportContext ctx;
        ctx.command = command;
        ctx.machine = machineDescription();
        ctx.revision = sourceRevision();
        ctx.wall_seconds = wall;
        ctx.markdown_path = out_md;
        ctx.images_dir = images;
        ctx.validation = ctx_validation;
        const std::string md = exp::buildReport(plan, runs, ctx);
        exp::writeReport(out_md, md);
        fmt::print("\n{}\n", md);
        fmt::print("wrote {} (charts in {}); run time {:.0f} s ({:.1f} min)\n", out_md, images, wall, wall / 60.0);
        return 0;
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-experiments: error: {}\n", e.what());
        return 1;
    }
}
