#include "experiment.h"

#include <fmt/format.h>
#include <pndt/data/gt_cloud.h>
#include <pndt/data/seg_noise.h>
#include <pndt/data/sequence_generator.h>
#include <pndt/eval/instance_ap.h>
#include <pndt/eval/panoptic_codec.h>
#include <pndt/instance_numbering.h>
#include <pndt/panoptic_map.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <set>
#include <unordered_map>

namespace pndt::exp
{
namespace
{
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string cm(double voxel) { return fmt::format("{:g}cm", std::round(voxel * 1000.0) / 10.0); }

/// The paper's defaults for the dataset the resolution imitates: ScanNet (640x480, 10 m,
/// theta_L/theta_Z = 0.7/0.1) or Hypersim (1024x768, 20 m, 0.7/0.4). Everything else is the
/// MapOptions default (theta_M/theta_N = 0.2/0.1, theta_St 0.9, theta_B 0.8, theta_O 0.25).
MapOptions baseOptions(const Plan& plan, double voxel)
{
    MapOptions o;
    o.voxel_size = voxel;
    o.max_range = plan.resolution == "1024x768" ? 20.0 : 10.0;
    o.theta_l = 0.7;
    o.theta_z = plan.resolution == "1024x768" ? 0.4 : 0.1;
    o.threads = 1;
    plan.rules.applyTo(o);
    return o;
}

RowSpec mapRow(std::string id, std::string group, std::string label, double voxel, Input input, MapOptions o,
               Readout readout = Readout::Propagated, std::string map_key = {})
{
    RowSpec r;
    r.id = std::move(id);
    r.group = std::move(group);
    r.label = std::move(label);
    r.voxel = voxel;
    r.input = input;
    r.readout = readout;
    r.map_key = map_key.empty() ? r.id : std::move(map_key);
    r.options = o;
    return r;
}

/// Semantic and panoptic output of the raw per-frame input.
eval::PredictedLabels rawLabels(const Image<uint16_t>& semantic, const Image<uint32_t>& instance)
{
    eval::PredictedLabels p;
    p.semantic.assign(semantic.data.begin(), semantic.data.end());
    p.panoptic = eval::encodePanoptic(semantic.data, instance.data);
    return p;
}

/// Share (percent) of elements with a benchmark GT class whose predicted semantic is not void.
struct Coverage
{
    uint64_t labelled = 0, correct = 0, total = 0;
    void add(const std::vector<uint32_t>& gt, const std::vector<uint16_t>& pred, const eval::Benchmark& b)
    {
        for (size_t i = 0; i < gt.size(); ++i)
        {
            const uint16_t g = eval::semanticOf(gt[i]);
            if (!b.isSemantic(g)) continue;
            ++total;
            labelled += pred[i] != 0 ? 1 : 0;
            correct += pred[i] == g ? 1 : 0;
        }
    }
    static double pct(uint64_t a, uint64_t b) { return b ? 100.0 * double(a) / double(b) : kNaN; }
    void fill(Scores& s, bool three_d) const
    {
        (three_d ? s.coverage3 : s.coverage2) = pct(labelled, total);
        (three_d ? s.accuracy3 : s.accuracy2) = pct(correct, total);
        (three_d ? s.precision3 : s.precision2) = pct(correct, labelled);
    }
};

/// The no-propagation readout: <argmax h^L, instance if argmax is a thing class, else 0>.
/// The instance part of the map's (propagated) output is the voxel's own top instance
/// whenever the voxel is a panoptic thing (pthing), else 0; only the class is propagated.
uint32_t noPropagationLabel(uint16_t semantic, uint32_t instance, const ClassSet& classes)
{
    return eval::encodePanoptic(semantic, classes.isThing(semantic) ? instance : 0);
}

struct EvalView
{
    Pose T_world_cam;
    std::vector<uint32_t> gt;  // sem << 16 | ins
};

struct MapSlot
{
    std::string key;
    Input input = Input::Network;
    std::unique_ptr<PanopticMap> map;
    std::vector<const RowSpec*> rows;
};
}  // namespace

const std::vector<std::string>& RuleThresholds::names()
{
    static const std::vector<std::string> n = {"split_coverage", "fragment_merge_frames", "fragment_absorb_ratio",
                                               "label_fill_distance"};
    return n;
}

double RuleThresholds::get(const std::string& name) const
{
    if (name == "split_coverage") return split_coverage;
    if (name == "fragment_merge_frames") return fragment_merge_frames;
    if (name == "fragment_absorb_ratio") return fragment_absorb_ratio;
    if (name == "label_fill_distance") return label_fill_distance;
    throw std::invalid_argument("unknown rule threshold '" + name + "'");
}

void RuleThresholds::set(const std::string& name, double value)
{
    if (name == "split_coverage") split_coverage = value;
    else if (name == "fragment_merge_frames") fragment_merge_frames = value;
    else if (name == "fragment_absorb_ratio") fragment_absorb_ratio = value;
    else if (name == "label_fill_distance") label_fill_distance = value;
    else throw std::invalid_argument("unknown rule threshold '" + name + "'");
}

void RuleThresholds::applyTo(MapOptions& o) const
{
    o.split_coverage = split_coverage;
    o.fragment_merge_frames = uint32_t(std::lround(fragment_merge_frames));
    o.fragment_absorb_ratio = fragment_absorb_ratio;
    o.label_fill_distance = label_fill_distance;
}

InputStats& InputStats::operator+=(const InputStats& o)
{
    pixels += o.pixels;
    pass += o.pass;
    pass_correct += o.pass_correct;
    fail_correct += o.fail_correct;
    thing_pixels += o.thing_pixels;
    thing_pass += o.thing_pass;
    dropped_split += o.dropped_split;
    dropped_merged += o.dropped_merged;
    dropped_other_thing += o.dropped_other_thing;
    dropped_stuff += o.dropped_stuff;
    return *this;
}

std::vector<RowSpec> makeRows(const Plan& plan)
{
    std::vector<RowSpec> rows;
    RowSpec raw;
    raw.id = "raw-net";
    raw.group = "net";
    raw.label = "raw input (per frame)";
    raw.raw = true;
    raw.input = Input::Network;
    rows.push_back(raw);
    for (double v : plan.voxels)
        rows.push_back(mapRow("ndt-net@" + cm(v), "net", "PanopticNDT", v, Input::Network, baseOptions(plan, v)));
    for (double v : plan.voxels)
    {
        MapOptions o = baseOptions(plan, v);
        o.applyPaperRules();
        rows.push_back(mapRow("paper-net@" + cm(v), "net", "paper preset (exact)", v, Input::Network, o));
    }
    for (double v : plan.voxels)
    {
        MapOptions o = baseOptions(plan, v);
        o.use_ndt = false;
        rows.push_back(mapRow("cube-net@" + cm(v), "net", "w/o NDT", v, Input::Network, o));
    }
    for (double v : plan.voxels)
        rows.push_back(mapRow("noprop-net@" + cm(v), "net", "w/o panoptic propagation", v, Input::Network,
                              baseOptions(plan, v), Readout::NoPropagation, "ndt-net@" + cm(v)));

    RowSpec raw_gt = raw;
    raw_gt.id = "raw-gt";
    raw_gt.group = "gt";
    raw_gt.label = "raw input (per frame)";
    raw_gt.input = Input::GroundTruth;
    rows.push_back(raw_gt);
    for (double v : plan.voxels)
        rows.push_back(mapRow("ndt-gt@" + cm(v), "gt", "PanopticNDT", v, Input::GroundTruth, baseOptions(plan, v)));

    if (!std::isnan(plan.tuned_theta_l))
        for (double v : plan.voxels)
        {
            MapOptions o = baseOptions(plan, v);
            o.theta_l = plan.tuned_theta_l;
            rows.push_back(mapRow("tuned-net@" + cm(v), "net",
                                  fmt::format("PanopticNDT, theta_L = {:g} (tuned on validation scenes)", o.theta_l), v,
                                  Input::Network, o));
        }

    const double a = plan.ablation_voxel;
    rows.push_back(mapRow("semonly-net@" + cm(a), "ablation", "semantic only (no instance input)", a,
                          Input::NetworkSemanticOnly, baseOptions(plan, a)));
    MapOptions lo = baseOptions(plan, a);
    lo.theta_m = 0.1;
    lo.theta_n = 0.05;
    rows.push_back(mapRow("thr-0.1-0.05@" + cm(a), "ablation", "theta_M/theta_N = 0.1/0.05", a, Input::Network, lo));
    MapOptions hi = baseOptions(plan, a);
    hi.theta_m = 0.3;
    hi.theta_n = 0.15;
    rows.push_back(mapRow("thr-0.3-0.15@" + cm(a), "ablation", "theta_M/theta_N = 0.3/0.15", a, Input::Network, hi));
    MapOptions paper_rules = baseOptions(plan, a);
    paper_rules.class_consistent_instances = false;
    paper_rules.split_coverage = 0;
    paper_rules.fragment_merge_frames = 0;
    paper_rules.fragment_absorb_ratio = 0;
    rows.push_back(mapRow("paper-instances@" + cm(a), "ablation", "the paper's instance rules", a, Input::Network,
                          paper_rules));
    MapOptions no_fill = baseOptions(plan, a);
    no_fill.label_fill_distance = 0;
    rows.push_back(mapRow("nofill-net@" + cm(a), "ablation", "w/o label fill", a, Input::Network, no_fill));
    // The speed-up's one approximation: one free-space ray per endpoint voxel.
    MapOptions per_pixel = baseOptions(plan, a);
    per_pixel.ray_mode = RayMode::PerPixel;
    rows.push_back(
        mapRow("perpixel-net@" + cm(a), "ablation", "per-pixel rays (no merged rays)", a, Input::Network, per_pixel));
    // An ablation voxel size outside the main list still needs its reference rows.
    if (std::find(plan.voxels.begin(), plan.voxels.end(), a) == plan.voxels.end())
    {
        rows.push_back(mapRow("ndt-net@" + cm(a), "ablation", "PanopticNDT", a, Input::Network, baseOptions(plan, a)));
        MapOptions o = baseOptions(plan, a);
        o.use_ndt = false;
        rows.push_back(mapRow("cube-net@" + cm(a), "ablation", "w/o NDT", a, Input::Network, o));
        rows.push_back(mapRow("noprop-net@" + cm(a), "ablation", "w/o panoptic propagation", a, Input::Network,
                              baseOptions(plan, a), Readout::NoPropagation, "ndt-net@" + cm(a)));
    }
    return rows;
}

double defaultValue(const std::string& param) { return param == "theta_l" ? 0.7 : RuleThresholds{}.get(param); }

std::string validationRowId(const std::string& param, double value)
{
    // Every parameter at its default is one map: the theta_L = 0.7 row.
    if (value == defaultValue(param)) return fmt::format("val-theta_l-{:g}", defaultValue("theta_l"));
    return fmt::format("val-{}-{:g}", param, value);
}
std::string validationRowId(double theta_l) { return validationRowId("theta_l", theta_l); }

std::vector<RowSpec> makeValidationRows(const Plan& plan, const Sweep& sweep)
{
    std::vector<RowSpec> rows = makeRows(plan);
    rows.erase(std::remove_if(rows.begin(), rows.end(), [](const RowSpec& r) { return r.id != "raw-net"; }),
               rows.end());
    std::set<std::string> made;
    for (const auto& [param, values] : sweep)
        for (double value : values)
        {
            const std::string id = validationRowId(param, value);
            if (!made.insert(id).second) continue;
            MapOptions o = baseOptions(plan, plan.ablation_voxel);
            if (param == "theta_l")
                o.theta_l = value;
            else
            {
                RuleThresholds r = plan.rules;
                r.set(param, value);
                r.applyTo(o);
            }
            rows.push_back(mapRow(id, "validation", fmt::format("PanopticNDT, {} = {:g}", param, value),
                                  plan.ablation_voxel, Input::Network, o));
        }
    return rows;
}

double validationCriterion(const ValidationResult& v, const std::string& param, double value)
{
    double sum = 0;
    size_t n = 0;
    for (const RunResult& r : v.runs)
    {
        auto it = r.scores.find(validationRowId(param, value));
        if (it == r.scores.end()) continue;
        const Scores& s = it->second;
        sum += (s.miou3 + s.pq3 + s.miou2 + s.pq2) / 4.0;
        ++n;
    }
    return n ? sum / double(n) : kNaN;
}
double validationCriterion(const ValidationResult& v, double theta_l)
{
    return validationCriterion(v, "theta_l", theta_l);
}

double chooseValue(const ValidationResult& v, const std::string& param)
{
    const double fallback = defaultValue(param), fallback_c = validationCriterion(v, param, fallback);
    double best = fallback, best_c = fallback_c;
    const auto it = v.sweep.find(param);
    if (it == v.sweep.end()) return best;
    for (double t : it->second)
    {
        const double c = validationCriterion(v, param, t);
        if (!std::isnan(c) && (std::isnan(best_c) || c > best_c)) best = t, best_c = c;
    }
    if (!std::isnan(fallback_c) && best_c <= fallback_c + kValidationTieMargin) return fallback;
    return best;
}
double chooseThetaL(const ValidationResult& v) { return chooseValue(v, "theta_l"); }

std::vector<std::string> pooledKeys(const Plan& plan)
{
    const std::string a = cm(plan.ablation_voxel);
    return {"raw-net/2d", "ndt-net@" + a + "/2d", "ndt-net@" + a + "/3d", "cube-net@" + a + "/3d",
            "ndt-gt@" + a + "/3d", "ndt-gt@" + a + "/2d"};
}

void fillScores(const eval::EvalResult& r, bool three_d, Scores& s)
{
    auto pct = [](double v) { return 100.0 * v; };
    if (three_d)
    {
        s.miou3 = pct(r.semantic.miou);
        s.miou_p3 = pct(r.panoptic_semantic.miou);
        s.pq3 = pct(r.pq.all.pq);
        s.ap50_3 = pct(r.ap.ap50);
    }
    else
    {
        s.miou2 = pct(r.semantic.miou);
        s.miou_p2 = pct(r.panoptic_semantic.miou);
        s.pq2 = pct(r.pq.all.pq);
        s.ap50_2 = pct(r.ap.ap50);
    }
}

RunResult runExperiment(const Plan& plan, const std::string& scene, uint64_t seed)
{
    const auto t_start = Clock::now();
    RunResult res;
    res.scene = scene;
    res.seed = seed;

    data::GeneratorOptions go;
    go.scene = scene;
    go.frames = plan.frames;
    go.resolution = plan.resolution;
    go.seg_noise = 1.0;
    go.depth_noise = 1.0;
    go.pose_noise = 0.0;
    go.seed = seed;
    const data::SequenceGenerator gen(go);
    res.scene_name = gen.sceneName();
    res.frames = gen.size();
    // The ground truth as a perfect network: seg-noise 0 (labels exact, scores 0.999,
    // instance ids freshly permuted in every frame, as the generator does for seg-noise 0).
    data::SegNoiseOptions gt_seg = go.seg;
    gt_seg.strength = 0.0;
    gt_seg.seed = seed;
    const data::SegmentationNoiseModel gt_model(gen.objects(), gt_seg);
    data::GtCloudBuilder cloud(0.01, gen.camera().max_range);
    const eval::Benchmark bench = eval::Benchmark::nyuv2_40();
    const std::vector<std::string> pooled = pooledKeys(plan);
    const std::set<std::string> pooled_set(pooled.begin(), pooled.end());

    // One map per distinct map_key; rows read them.
    std::vector<MapSlot> slots;
    bool need_gt_input = false;
    for (const RowSpec& r : plan.rows)
    {
        if (r.input == Input::GroundTruth) need_gt_input = true;
        if (r.raw) continue;
        auto it = std::find_if(slots.begin(), slots.end(), [&](const MapSlot& s) { return s.key == r.map_key; });
        if (it == slots.end())
        {
            MapSlot s;
            s.key = r.map_key;
            s.input = r.input;
            s.map = std::make_unique<PanopticMap>(r.options);
            slots.push_back(std::move(s));
            it = slots.end() - 1;
        }
        it->rows.push_back(&r);
    }
    std::map<std::string, eval::PanopticEvaluator> ev2, ev3;
    std::map<std::string, eval::InstanceAP> ap3_scored;  // AP with the map's confidences
    for (const RowSpec& r : plan.rows)
    {
        ev2.emplace(r.id, eval::PanopticEvaluator(bench));
        if (!r.raw) ev3.emplace(r.id, eval::PanopticEvaluator(bench));
        if (!r.raw) ap3_scored.emplace(r.id, eval::InstanceAP(bench));
    }
    std::map<std::string, Coverage> cov2, cov3;

    // ---- frames: generate once, integrate into every map
    std::vector<EvalView> views;
    for (size_t i = 0; i < gen.size(); ++i)
    {
        auto t0 = Clock::now();
        data::GeneratedFrame f = gen.frame(i);
        cloud.add(f.depth_clean, f.geometry, f.gt_semantic, f.gt_instance);
        const PanopticFrame net = f.panopticFrame();
        PanopticFrame gtf, semf;
        data::SegNoiseFrame gtp;
        if (need_gt_input)
        {
            gtp = gt_model.apply(f.gt_semantic, f.gt_instance, f.depth_clean, f.geometry, i);
            gtf = net;
            gtf.semantic = gtp.semantic;
            gtf.semantic_score = gtp.semantic_score;
            gtf.instance = gtp.instance;
            gtf.panoptic_score = gtp.panoptic_score;
        }
        {
            const data::SegNoiseFrame& p = f.prediction;
            const MapOptions mo = baseOptions(plan, plan.ablation_voxel);
            std::unordered_map<uint32_t, const data::InstanceOutcome*> outcome;
            for (const data::InstanceOutcome& o : p.outcomes) outcome[o.gt_instance] = &o;
            for (size_t k = 0; k < p.semantic.size(); ++k)
            {
                const uint16_t g = f.gt_semantic.data[k];
                if (!bench.isSemantic(g)) continue;
                const bool pass = p.semantic.data[k] != 0 && p.semantic_score.data[k] > mo.theta_l;
                const bool correct = p.semantic.data[k] == g;
                ++res.input.pixels;
                res.input.pass += pass;
                res.input.pass_correct += pass && correct;
                res.input.fail_correct += !pass && correct;
                if (!pass && correct)
                {
                    auto it = bench.isThing(g) ? outcome.find(f.gt_instance.data[k]) : outcome.end();
                    if (!bench.isThing(g))
                        ++res.input.dropped_stuff;
                    else if (it != outcome.end() && it->second->split)
                        ++res.input.dropped_split;
                    else if (it != outcome.end() && it->second->merged)
                        ++res.input.dropped_merged;
                    else
                        ++res.input.dropped_other_thing;
                }
                if (bench.isThing(g))
                {
                    ++res.input.thing_pixels;
                    res.input.thing_pass += bench.isThing(p.semantic.data[k]) && p.instance.data[k] != 0 &&
                                            p.panoptic_score.data[k] > mo.theta_z;
                }
            }
        }
        {
            // Per GT thing instance: is it mostly right in this view?
            struct Seen
            {
                uint64_t pixels = 0, correct = 0, usable = 0;
            };
            const double theta_l = baseOptions(plan, plan.ablation_voxel).theta_l;
            std::unordered_map<uint32_t, Seen> seen;
            for (size_t k = 0; k < f.gt_semantic.size(); ++k)
            {
                const uint16_t g = f.gt_semantic.data[k];
                if (!bench.isInstance(g)) continue;
                Seen& c = seen[eval::encodePanoptic(g, f.gt_instance.data[k])];
                ++c.pixels;
                const bool right = f.prediction.semantic.data[k] == g;
                c.correct += right ? 1 : 0;
                c.usable += right && f.prediction.semantic_score.data[k] > theta_l ? 1 : 0;
            }
            for (const auto& [label, c] : seen)
            {
                if (c.pixels < 100) continue;
                ObjectViews& o = res.objects[label];
                ++o.views;
                o.views_right += 2 * c.correct > c.pixels ? 1 : 0;
                o.views_usable += 2 * c.usable > c.pixels ? 1 : 0;
                o.pixels += c.pixels;
                o.correct += c.correct;
            }
        }
        semf = net;
        semf.instance = {};
        semf.panoptic_score = {};
        res.seconds_generate += since(t0);

        t0 = Clock::now();
        for (MapSlot& s : slots)
        {
            const PanopticFrame& in = s.input == Input::GroundTruth ? gtf
                                      : s.input == Input::NetworkSemanticOnly ? semf
                                                                              : net;
            s.map->integrate(in, f.T_world_cam_reported);
        }
        res.seconds_integrate += since(t0);

        if (plan.eval_every > 0 && i % size_t(plan.eval_every) == 0)
        {
            t0 = Clock::now();
            EvalView v;
            v.T_world_cam = f.T_world_cam;
            v.gt = eval::encodePanoptic(f.gt_semantic.data, f.gt_instance.data);
            for (const RowSpec& r : plan.rows)
            {
                if (!r.raw) continue;
                const eval::PredictedLabels p = r.input == Input::GroundTruth ? rawLabels(gtp.semantic, gtp.instance)
                                                                              : rawLabels(f.prediction.semantic,
                                                                                          f.prediction.instance);
                ev2.at(r.id).add(v.gt, p);
                res.seg2d[r.id] += analyseSegments(v.gt, p.panoptic, bench);
                cov2[r.id].add(v.gt, p.semantic, bench);
                if (pooled_set.count(r.id + "/2d"))
                    res.pooled.push_back({r.id + "/2d", std::make_shared<const std::vector<uint32_t>>(v.gt), p});
            }
            views.push_back(std::move(v));
            res.seconds_eval += since(t0);
        }
        if (plan.verbose && ((i + 1) % 10 == 0 || i + 1 == gen.size()))
            fmt::print("  [{} seed {}] frame {}/{}\n", scene, seed, i + 1, gen.size());
    }
    res.eval_frames = views.size();

    // ---- evaluation
    auto t0 = Clock::now();
    const std::vector<data::GtPoint> gt_points = cloud.build();
    res.gt_points = gt_points.size();
    std::vector<Eigen::Vector3d> points(gt_points.size());
    auto gt3 = std::make_shared<std::vector<uint32_t>>(gt_points.size());
    for (size_t i = 0; i < gt_points.size(); ++i)
    {
        points[i] = gt_points[i].position.cast<double>();
        (*gt3)[i] = gt_points[i].label;
    }
    {
        std::unordered_map<uint32_t, uint32_t> count;
        for (uint32_t l : *gt3)
            if (bench.isInstance(eval::semanticOf(l))) ++count[l];
        for (const auto& [l, n] : count) res.gt_instances3 += n >= 100 ? 1 : 0;
    }
    std::shared_ptr<const std::vector<uint32_t>> gt3c = gt3;
    const CameraIntrinsics K = gen.camera().K;
    const ClassSet classes = slots.empty() ? ClassSet::nyuv2_40() : slots.front().map->options().classes;
    for (MapSlot& s : slots)
    {
        const PanopticMap& map = *s.map;
        map.finalize();
        bool need_noprop = false;
        for (const RowSpec* r : s.rows) need_noprop |= r->readout == Readout::NoPropagation;
        // 3D: labelAt over the GT points (the map's nearest Gaussian among 27 voxels).
        // Instances numbered densely (ids of later short-term maps exceed the 16-bit field).
        const InstanceNumbering numbering = InstanceNumbering::of(map);
        eval::PredictedLabels prop, noprop;
        prop.semantic.assign(points.size(), 0);
        prop.panoptic.assign(points.size(), 0);
        if (need_noprop) noprop.panoptic.assign(points.size(), 0);
        for (size_t i = 0; i < points.size(); ++i)
        {
            const PointLabel l = map.labelAt(points[i]);
            if (!l.found) continue;
            prop.semantic[i] = l.semantic;
            const uint32_t ins = numbering.dense(l.panoptic.instance);
            prop.panoptic[i] = eval::encodePanoptic(l.panoptic.semantic, ins);
            if (need_noprop) noprop.panoptic[i] = noPropagationLabel(l.semantic, ins, classes);
        }
        if (need_noprop) noprop.semantic = std::vector<uint16_t>(prop.semantic);
        const size_t n_instances = map.instances().size();
        tsl::robin_map<uint32_t, double> confidence_of;
        for (const MapInstance& mi : map.instances()) confidence_of[mi.id] = mi.confidence;
        const auto confidence = [&](uint16_t, uint32_t dense) { return confidence_of.at(numbering.mapId(dense)); };
        for (const RowSpec* r : s.rows)
        {
            const eval::PredictedLabels& p = r->readout == Readout::NoPropagation ? noprop : prop;
            ev3.at(r->id).add(*gt3c, p);
            ap3_scored.at(r->id).add(*gt3c, eval::instancesFromPanoptic(p.panoptic, bench, confidence));
            if (r->id == "ndt-net@" + cm(plan.ablation_voxel) || r->id == "tuned-net@" + cm(plan.ablation_voxel))
            {
                auto& objs = res.object_points[r->id];
                for (size_t i = 0; i < gt3c->size(); ++i)
                {
                    const uint32_t g = (*gt3c)[i];
                    if (!bench.isInstance(eval::semanticOf(g))) continue;
                    ObjectPoints& o = objs[g];
                    ++o.points;
                    o.labelled += p.semantic[i] != 0 ? 1 : 0;
                    o.correct += p.semantic[i] == eval::semanticOf(g) ? 1 : 0;
                }
            }
            const bool detail = plan.details && r->id == "ndt-net@" + cm(plan.ablation_voxel);
            res.seg3d[r->id] = analyseSegments(*gt3c, p.panoptic, bench, 100, detail ? &res.details3 : nullptr);
            cov3[r->id].add(*gt3c, p.semantic, bench);
            res.map_instances[r->id] = n_instances;
            if (pooled_set.count(r->id + "/3d")) res.pooled.push_back({r->id + "/3d", gt3c, p});
        }
        // 2D: the map rendered into the evaluated frames.
        RenderedView view;
        for (const EvalView& v : views)
        {
            map.render(v.T_world_cam, K, view);
            eval::PredictedLabels vp;
            vp.semantic.assign(view.semantic.data.begin(), view.semantic.data.end());
            vp.panoptic.resize(vp.semantic.size());
            for (size_t i = 0; i < vp.panoptic.size(); ++i)
                vp.panoptic[i] =
                    eval::encodePanoptic(view.panoptic_semantic.data[i], numbering.dense(view.instance.data[i]));
            eval::PredictedLabels vn;
            if (need_noprop)
            {
                vn.semantic = std::vector<uint16_t>(vp.semantic);
                vn.panoptic.resize(vp.semantic.size());
                for (size_t i = 0; i < vn.panoptic.size(); ++i)
                    vn.panoptic[i] =
                        noPropagationLabel(view.semantic.data[i], numbering.dense(view.instance.data[i]), classes);
            }
            std::shared_ptr<const std::vector<uint32_t>> gtv;
            for (const RowSpec* r : s.rows)
            {
                const eval::PredictedLabels& p = r->readout == Readout::NoPropagation ? vn : vp;
                ev2.at(r->id).add(v.gt, p);
                res.seg2d[r->id] += analyseSegments(v.gt, p.panoptic, bench);
                cov2[r->id].add(v.gt, p.semantic, bench);
                if (pooled_set.count(r->id + "/2d"))
                {
                    if (!gtv) gtv = std::make_shared<const std::vector<uint32_t>>(v.gt);
                    res.pooled.push_back({r->id + "/2d", gtv, p});
                }
            }
        }
        s.map.reset();  // free the memory early
    }
    for (const RowSpec& r : plan.rows)
    {
        Scores sc;
        fillScores(ev2.at(r.id).result(), false, sc);
        cov2[r.id].fill(sc, false);
        if (!r.raw)
        {
            fillScores(ev3.at(r.id).result(), true, sc);
            sc.ap50_3s = 100.0 * ap3_scored.at(r.id).result().ap50;
            cov3[r.id].fill(sc, true);
        }
        res.scores[r.id] = sc;
    }
    res.seconds_eval += since(t0);
    res.seconds = since(t_start);
    return res;
}

}  // namespace pndt::exp
