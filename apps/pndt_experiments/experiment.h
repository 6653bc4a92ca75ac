// One experiment run of pndt-experiments: a synthetic sequence (scene, seed) is generated
// once, frame by frame, and every frame is integrated into all map variants side by side
// (network-like input, ground-truth input, ablations). Afterwards each map is evaluated in
// 3D (PanopticMap::labelAt over the generated GT cloud) and in 2D (the map rendered into
// every k-th frame), and the raw per-frame input is scored on the same frames.
#pragma once

#include <pndt/eval/panoptic_evaluator.h>
#include <pndt/map_options.h>

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "diagnostics.h"

namespace pndt::exp
{
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// What a map is fed with.
enum class Input
{
    Network,              ///< the simulated network output (seg-noise strength 1)
    GroundTruth,          ///< the ground truth as a perfect network (seg-noise 0: ids permuted per frame)
    NetworkSemanticOnly,  ///< the network output without instance images (no matching at all)
};

/// How the map's labels are read.
enum class Readout
{
    Propagated,     ///< the map's panoptic output (labelAt / render): propagated labels
    NoPropagation,  ///< per voxel: <argmax h^L, its own top instance if that class is a thing, else 0>
};

/// One row of the result tables.
struct RowSpec
{
    std::string id;     ///< unique key, e.g. "ndt-net@0.10"
    std::string group;  ///< "net", "gt", "ablation"
    std::string label;  ///< printed method name
    double voxel = 0;   ///< metres; 0 = the raw per-frame input (2D only)
    bool raw = false;   ///< the raw input (no map)
    Input input = Input::Network;
    Readout readout = Readout::Propagated;
    /// Map options (only for maps); equal `map_key` = the same map, read differently.
    std::string map_key;
    MapOptions options;
};

/// The thresholds of our rules beyond the paper (map_options.h), chosen on the
/// validation scenes. They start from MapOptions' defaults (the values an earlier
/// validation chose), so a run that chooses them again reports what users run.
struct RuleThresholds
{
    double split_coverage = MapOptions{}.split_coverage;
    double fragment_merge_frames = MapOptions{}.fragment_merge_frames;
    double fragment_absorb_ratio = MapOptions{}.fragment_absorb_ratio;
    double label_fill_distance = MapOptions{}.label_fill_distance;
    /// Names of the swept parameters, in order.
    static const std::vector<std::string>& names();
    double get(const std::string& name) const;
    void set(const std::string& name, double value);
    void applyTo(MapOptions& o) const;
};

struct Plan
{
    std::vector<std::string> scenes;
    std::vector<uint64_t> seeds;
    int frames = 60;
    std::string resolution = "640x480";
    int eval_every = 5;                ///< 2D: render the map into frames 0, k, 2k, ...
    std::vector<double> voxels;        ///< PanopticNDT / w/o NDT / no propagation / GT input
    double ablation_voxel = 0.10;      ///< semantic-only and threshold ablations
    int jobs = 1;                      ///< runs in parallel
    bool verbose = false;
    bool details = false;              ///< print every GT thing segment's outcome (3D, main map)
    std::vector<RowSpec> rows;         ///< filled by makeRows()
    /// theta_L chosen on the validation scenes; NaN = no "tuned" rows.
    double tuned_theta_l = kNaN;
    /// Our rules' thresholds for every map row (chosen on the validation scenes).
    RuleThresholds rules;
};

/// Values tried on the validation scenes per parameter ("theta_l" and RuleThresholds::names()).
using Sweep = std::map<std::string, std::vector<double>>;
/// Validation: the network-input PanopticNDT map at the ablation voxel size for every
/// value of every swept parameter, one parameter varied at a time from the defaults
/// (row ids "val-<param>-<value>"; the defaults' map is "val-theta_l-0.7"), plus the raw input.
std::vector<RowSpec> makeValidationRows(const Plan& plan, const Sweep& sweep);
std::string validationRowId(const std::string& param, double value);
std::string validationRowId(double theta_l);
/// The value of `param` the plan's defaults use (theta_l: 0.7).
double defaultValue(const std::string& param);

/// The rows of the tables for a plan (raw inputs, maps, query-side ablations).
std::vector<RowSpec> makeRows(const Plan& plan);

/// Scores in percent; NaN = not applicable.
struct Scores
{
    double miou3 = kNaN, miou_p3 = kNaN, pq3 = kNaN, ap50_3 = kNaN;
    double ap50_3s = kNaN;  ///< 3D AP50 with the map's instance confidences (ap50_3: every score 1)
    double miou2 = kNaN, miou_p2 = kNaN, pq2 = kNaN, ap50_2 = kNaN;
    double coverage3 = kNaN, coverage2 = kNaN;  ///< share of non-void GT the map labels at all
    double accuracy3 = kNaN, accuracy2 = kNaN;  ///< share of non-void GT with the right class (argmax h^L)
    double precision3 = kNaN, precision2 = kNaN;///< right class among the labelled (non-void) ones
};

/// The raw network input of all frames of a run against the GT, split by the map's
/// semantic score filter (S^L > theta_L; pixels with benchmark GT only).
struct InputStats
{
    uint64_t pixels = 0, pass = 0, pass_correct = 0, fail_correct = 0;
    uint64_t thing_pixels = 0, thing_pass = 0;  ///< GT thing pixels; predicted as a thing with S^P > theta_Z
    /// Right-class pixels the filter drops, by what the generator did to their GT object in that
    /// frame: split (over-segmented), merged with a neighbour, neither (things), or stuff pixels.
    uint64_t dropped_split = 0, dropped_merged = 0, dropped_other_thing = 0, dropped_stuff = 0;
    InputStats& operator+=(const InputStats& o);
};

/// Scores of an evaluation result (fractions -> percent).
void fillScores(const eval::EvalResult& r, bool three_d, Scores& s);

/// One GT thing instance as the raw input saw it over all frames.
struct ObjectViews
{
    uint32_t views = 0;        ///< frames with >= 100 visible pixels of it
    uint32_t views_right = 0;  ///< of those, frames where most of its pixels have the right class
    uint32_t views_usable = 0; ///< frames where most of its pixels have the right class and S^L > theta_L
    uint64_t pixels = 0, correct = 0;  ///< over those frames
};
/// One GT thing instance in the 3D evaluation of a map.
struct ObjectPoints
{
    uint64_t points = 0, labelled = 0, correct = 0;  ///< correct: argmax h^L = GT class
};

struct RunResult
{
    std::string scene, scene_name;
    uint64_t seed = 0;
    size_t frames = 0, eval_frames = 0, gt_points = 0;
    size_t gt_instances3 = 0;  ///< GT thing instances with >= 100 points in the cloud
    std::map<std::string, Scores> scores;        ///< by RowSpec::id
    std::map<std::string, SegmentStats> seg2d;   ///< segment outcomes (2D), by RowSpec::id
    std::map<std::string, SegmentStats> seg3d;   ///< segment outcomes (3D), by RowSpec::id
    std::map<std::string, size_t> map_instances; ///< instances() of each map, by RowSpec::id
    InputStats input;                            ///< the network input of all frames
    std::map<uint32_t, ObjectViews> objects;     ///< GT thing instances (sem << 16 | ins), raw input
    /// "ndt-net@<a>" / "tuned-net@<a>" -> GT thing instance -> its points in that map.
    std::map<std::string, std::map<uint32_t, ObjectPoints>> object_points;
    std::vector<SegmentDetail> details3;         ///< --details: PanopticNDT at the ablation voxel, 3D
    /// Labels of the rows in pooledKeys(), for per-class results pooled over all runs
    /// (added to one evaluator per key in run order, so the pooled AP does not depend on
    /// --jobs). 3D: one item per run; 2D: one per evaluated frame.
    struct PooledItem
    {
        std::string key;  ///< "<row id>/2d" or "<row id>/3d"
        std::shared_ptr<const std::vector<uint32_t>> gt;  ///< shared by the rows of a run / frame
        eval::PredictedLabels pred;
    };
    std::vector<PooledItem> pooled;
    double seconds = 0, seconds_generate = 0, seconds_integrate = 0, seconds_eval = 0;
};

/// Row ids whose per-class results are pooled over runs (for the per-class tables / chart).
std::vector<std::string> pooledKeys(const Plan& plan);

/// The sweeps on the validation scenes.
struct ValidationResult
{
    Plan plan;
    Sweep sweep;
    std::vector<RunResult> runs;
    double chosen = 0.7;       ///< theta_L
    RuleThresholds rules;      ///< our rules' thresholds
};
/// Selection criterion of a parameter value: the mean over the validation runs of
/// (3D mIoU + 3D PQ + 2D mIoU + 2D PQ) / 4 of the network-input map.
double validationCriterion(const ValidationResult& v, const std::string& param, double value);
double validationCriterion(const ValidationResult& v, double theta_l);
/// A value must beat the default's criterion by more than this (percent points)
/// to replace it: smaller gains are below what four validation runs can tell apart.
constexpr double kValidationTieMargin = 0.1;
/// The value of `param` with the highest criterion, if that beats the default's
/// by more than kValidationTieMargin, else the default (ties: the first listed).
double chooseValue(const ValidationResult& v, const std::string& param);
double chooseThetaL(const ValidationResult& v);

/// Runs one (scene, seed). Thread-safe (no shared state); throws on errors.
RunResult runExperiment(const Plan& plan, const std::string& scene, uint64_t seed);

}  // namespace pndt::exp
