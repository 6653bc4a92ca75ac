// pndt-refine-bench: what frame-to-map pose refinement (libs/pndt_refine) buys against a
// drifting, jittering localiser, and what it costs. Prints numbers; not a test.
//
//   pndt-refine-bench --scenes held_living --seeds 1 --strengths 1,2,4 --voxel 0.10
//       generated sequences (pndt-generate's pose noise at each strength): per strength a map
//       at the reported poses and one at the refined poses, next to the noise-free map; ATE /
//       RPE against the true poses, 3D mIoU / PQ over the GT cloud, 2D PQ rendered at the true
//       poses of every 5th frame, refinement ms/frame.
//   pndt-refine-bench --recording ../shared/data/redwood-livingroom1-micro --strengths 1,2,4
//       a recording with a trajectory: the trajectory perturbed with the same noise model,
//       refined; ATE against the given trajectory (geometry only).
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <pndt/data/gt_cloud.h>
#include <pndt/data/pose_noise.h>
#include <pndt/data/sequence_generator.h>
#include <pndt/eval/map_eval.h>
#include <pndt/io/pose_interpolator.h>
#include <pndt/io/sequence.h>
#include <pndt/panoptic_map.h>
#include <pndt/refine/pose_refiner.h>
#include <pndt/refine/time_offset.h>

#include <chrono>
#include <cstdlib>
#include <memory>
#include <sstream>

using namespace pndt;

namespace
{
template <typename T>
std::vector<T> parseList(const std::string& s)
{
    std::vector<T> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
    {
        std::istringstream is(item);
        T v;
        is >> v;
        if (is.fail()) throw std::invalid_argument("bad list item '" + item + "'");
        out.push_back(v);
    }
    return out;
}

struct Variant
{
    std::string name;
    double strength = 0;
    bool refine = false;
    std::vector<Pose> reported;  ///< what the localiser says
    std::vector<Pose> used;      ///< where the frames were integrated
    std::unique_ptr<PanopticMap> map;
    std::unique_ptr<refine::PoseRefiner> refiner;
    refine::TimeOffsetEstimator time_offset;
    const std::vector<double>* stamps = nullptr;
    double seconds_refine = 0, seconds_max = 0;
    const std::vector<Pose>* truth = nullptr;
};

struct Row
{
    std::string run, variant;
    refine::TrajectoryError te;
    double miou3 = -1, pq3 = -1, pq2 = -1, ms = 0, ms_max = 0;
    std::string refine_summary, time_offset;
};

void printRows(const std::vector<Row>& rows, bool quality)
{
    fmt::print("\n| run | poses | ATE cm | RPE cm/frame | RPE deg/frame |{} refine ms/frame (max) | refiner |\n",
               quality ? " 3D mIoU | 3D PQ | 2D PQ |" : "");
    fmt::print("|---|---|---|---|---|{}---|---|\n", quality ? "---|---|---|" : "");
    for (const Row& r : rows)
    {
        std::string q;
        if (quality) q = fmt::format(" {:.1f} | {:.1f} | {:.1f} |", r.miou3, r.pq3, r.pq2);
        fmt::print("| {} | {} | {:.2f} | {:.2f} | {:.3f} |{} {} | {} |\n", r.run, r.variant, 100 * r.te.ate_rmse,
                   100 * r.te.rpe_translation, r.te.rpe_rotation * 180 / 3.14159265358979, q,
                   r.ms > 0 ? fmt::format("{:.1f} ({:.0f})", r.ms, r.ms_max) : std::string("-"),
                   r.refine_summary.empty() ? "-" : r.refine_summary);
    }
    fmt::print("\ncamera / localiser time offset estimated from the refined poses:\n");
    for (const Row& r : rows)
        if (!r.time_offset.empty()) fmt::print("- {} {}: {}\n", r.run, r.variant, r.time_offset);
}

/// What a localiser late by `lag` seconds reports at each frame stamp: the trajectory at
/// stamp - lag (interpolated between frames; held at the first pose before it).
std::vector<Pose> lagging(const std::vector<Pose>& poses, const std::vector<double>& stamps, double lag)
{
    if (lag == 0) return poses;
    std::vector<Pose> out(poses.size());
    for (size_t i = 0; i < poses.size(); ++i)
    {
        const double s = stamps[i] - lag;
        size_t j = size_t(std::upper_bound(stamps.begin(), stamps.end(), s) - stamps.begin());
        if (j == 0) out[i] = poses.front();
        else if (j >= poses.size()) out[i] = poses.back();
        else out[i] = io::interpolatePose(poses[j - 1], poses[j], (s - stamps[j - 1]) / (stamps[j] - stamps[j - 1]));
    }
    return out;
}

void integrateVariant(Variant& v, const PanopticFrame& f, size_t i)
{
    Pose T = v.reported[i];
    if (v.refine)
    {
        const auto r = v.refiner->refine(*v.map, f, T);
        T = r.pose;
        v.seconds_refine += r.seconds;
        v.seconds_max = std::max(v.seconds_max, r.seconds);
        v.time_offset.add((*v.stamps)[i], v.reported[i], r.pose, r.accepted());
        if (std::getenv("PNDT_REFINE_TRACE") && v.truth)
        {
            const Pose e0 = (*v.truth)[i].inverse() * r.warm_start, e1 = (*v.truth)[i].inverse() * r.pose;
            fmt::print(stderr, "{} #{}: {} pts {} assoc {} it {} ratio {:.4f} step {:.1f} mm {:.2f} deg | err {:.1f} -> {:.1f} mm, {:.2f} -> {:.2f} deg, {:.0f} ms\n",
                       v.name, i, refine::outcomeName(r.outcome), r.points, r.associated, r.iterations, r.eigen_ratio,
                       1000 * r.step_translation, r.step_rotation * 57.2958, 1000 * e0.translation().norm(),
                       1000 * e1.translation().norm(), Eigen::AngleAxisd(e0.linear()).angle() * 57.2958,
                       Eigen::AngleAxisd(e1.linear()).angle() * 57.2958, 1000 * r.seconds);
        }
    }
    v.used.push_back(T);
    v.map->integrate(f, T);
}
}  // namespace

int main(int argc, char** argv)
{
    CLI::App app("pndt-refine-bench: NDT frame-to-map pose refinement against pose noise");
    std::string scenes = "held_living", seeds = "1", strengths = "1,2,4", recording;
    double voxel = 0.10;
    int frames = 60, eval_every = 5, max_frames = 0;
    double depth_noise = 1.0;
    refine::RefineOptions ro;
    ro.enabled = true;
    std::string loss = "cauchy";
    bool no_quality = false;
    double time_offset = 0;
    const std::vector<double>* stamps_now = nullptr;  // the frame stamps of the sequence being run
    app.add_option("--scenes", scenes, "generated scenes (report on held_*, tune on bedroom / dining)")
        ->capture_default_str();
    app.add_option("--seeds", seeds, "recording seeds (also the pose-noise seeds)")->capture_default_str();
    app.add_option("--strengths", strengths, "pose-noise strengths (pndt-generate --pose-noise)")->capture_default_str();
    app.add_option("--voxel", voxel, "map voxel size, metres")->capture_default_str();
    app.add_option("--frames", frames, "frames per generated sequence")->capture_default_str();
    app.add_option("--depth-noise", depth_noise, "generated depth noise strength")->capture_default_str();
    app.add_option("--eval-every", eval_every, "2D evaluation on every n-th frame")->capture_default_str();
    app.add_option("--recording", recording, "a Redwood folder with trajectory.log instead of generated scenes");
    app.add_option("--max-frames", max_frames, "recording: first n frames only (0 = all)");
    app.add_flag("--no-quality", no_quality, "skip the map evaluation");
    app.add_option("--time-offset", time_offset,
                   "the localiser is late by this many seconds: each frame gets the (noisy) pose of stamp - S")
        ->capture_default_str();
    app.add_option("--loss", loss, "cauchy, huber or none")->capture_default_str();
    app.add_option("--loss-scale", ro.loss_scale, "robust loss scale, sigmas")->capture_default_str();
    app.add_option("--min-sigma", ro.min_sigma_ratio, "coarse covariance floor, fraction of a voxel")->capture_default_str();
    app.add_option("--fine-sigma", ro.fine_sigma_ratio, "fine covariance floor (0: no fine solve)")->capture_default_str();
    app.add_option("--thing-weight", ro.thing_weight, "residual weight of thing classes")->capture_default_str();
    app.add_option("--min-eigen-ratio", ro.min_eigen_ratio, "degeneracy threshold")->capture_default_str();
    app.add_option("--gate", ro.gate_sigma, "association gate, sigmas")->capture_default_str();
    app.add_option("--min-samples", ro.min_samples, "map voxels need this many samples")->capture_default_str();
    app.add_option("--max-points", ro.max_points, "subsampled points per frame")->capture_default_str();
    app.add_option("--pixel-step", ro.pixel_step, "read every n-th pixel")->capture_default_str();
    bool no_carry = false;  // a plain flag: CLI11 shows a negated one as "--no-carry{false}"
    app.add_flag("--no-carry", no_carry, "do not carry the correction to the next frame");
    CLI11_PARSE(app, argc, argv);
    if (no_carry) ro.carry_correction = false;
    try
    {
        ro.loss = loss == "huber" ? refine::RobustLoss::Huber : loss == "none" ? refine::RobustLoss::None
                                                                               : refine::RobustLoss::Cauchy;
        const std::vector<double> strength_list = parseList<double>(strengths);
        std::vector<Row> rows;
        MapOptions mo;
        mo.voxel_size = voxel;
        auto makeVariants = [&](const std::vector<Pose>& truth, uint64_t seed, bool with_truth) {
            std::vector<Variant> vs;
            if (with_truth)
            {
                Variant v;
                v.name = "true poses";
                v.reported = truth;
                vs.push_back(std::move(v));
            }
            for (double s : strength_list)
                for (bool refine : {false, true})
                {
                    Variant v;
                    v.strength = s;
                    v.refine = refine;
                    v.name = fmt::format("noise {} {}", s, refine ? "refined" : "reported");
                    data::PoseNoiseOptions pn;
                    pn.strength = s;
                    pn.seed = seed;
                    v.reported = lagging(data::perturbPoses(truth, pn), *stamps_now, time_offset);
                    vs.push_back(std::move(v));
                }
            for (Variant& v : vs)
            {
                v.map = std::make_unique<PanopticMap>(mo);
                if (v.refine) v.refiner = std::make_unique<refine::PoseRefiner>(ro);
                v.truth = &truth;
                v.stamps = stamps_now;
            }
            return vs;
        };
        auto finishRows = [&](const std::string& run, std::vector<Variant>& vs, const std::vector<Pose>& truth) {
            for (Variant& v : vs)
            {
                Row r;
                r.run = run;
                r.variant = v.name;
                r.te = refine::trajectoryError(v.used, std::vector<Pose>(truth.begin(), truth.begin() + v.used.size()));
                if (v.refine)
                {
                    r.ms = 1000 * v.seconds_refine / double(v.used.size());
                    r.ms_max = 1000 * v.seconds_max;
                    r.refine_summary = v.refiner->stats().summary();
                    r.time_offset = v.time_offset.estimate().summary();
                }
                rows.push_back(r);
            }
        };

        if (!recording.empty())
        {
            const io::RgbdSequence seq = io::openRedwoodSequence(recording);
            size_t n = seq.size();
            if (max_frames > 0) n = std::min(n, size_t(max_frames));
            std::vector<Pose> truth;
            for (size_t i = 0; i < n; ++i)
            {
                if (!seq.frames[i].T_world_cam) throw InputError("frame without a pose in " + recording);
                truth.push_back(*seq.frames[i].T_world_cam);
            }
            std::vector<double> stamps(n);
            for (size_t i = 0; i < n; ++i) stamps[i] = seq.frames[i].t;
            stamps_now = &stamps;
            for (uint64_t seed : parseList<uint64_t>(seeds))
            {
                std::vector<Variant> vs = makeVariants(truth, seed, false);
                const io::FrameLoadOptions lo{false, false, false};
                for (size_t i = 0; i < n; ++i)
                {
                    const io::RgbdFrame rf = seq.load(i, lo);
                    PanopticFrame f;
                    f.K = rf.K;
                    f.depth = rf.depth;
                    f.source = recording + " #" + rf.id;
                    for (Variant& v : vs) integrateVariant(v, f, i);
                }
                finishRows(fmt::format("{} seed {}", seq.kind, seed), vs, truth);
            }
            printRows(rows, false);
            return 0;
        }

        for (const std::string& scene : parseList<std::string>(scenes))
            for (uint64_t seed : parseList<uint64_t>(seeds))
            {
                data::GeneratorOptions go;
                go.scene = scene;
                go.frames = frames;
                go.seed = seed;
                go.depth_noise = depth_noise;
                const data::SequenceGenerator gen(go);
                const std::vector<Pose>& truth = gen.truePoses();
                std::vector<double> stamps(truth.size());
                for (size_t i = 0; i < stamps.size(); ++i) stamps[i] = go.start_time + double(i) * go.frame_period;
                stamps_now = &stamps;
                std::vector<Variant> vs = makeVariants(truth, seed, true);
                data::GtCloudBuilder cloud(0.01, gen.camera().max_range);
                struct View
                {
                    Pose T;
                    Image<uint16_t> sem;
                    Image<uint32_t> ins;
                };
                std::vector<View> views;
                for (size_t i = 0; i < gen.size(); ++i)
                {
                    const data::GeneratedFrame g = gen.frame(i);
                    if (!no_quality)
                    {
                        cloud.add(g.depth_clean, g.geometry, g.gt_semantic, g.gt_instance);
                        if (i % size_t(eval_every) == 0) views.push_back({g.T_world_cam, g.gt_semantic, g.gt_instance});
                    }
                    const PanopticFrame f = g.panopticFrame();
                    for (Variant& v : vs) integrateVariant(v, f, i);
                    fmt::print(stderr, "\r{} seed {}: frame {}/{}", scene, seed, i + 1, gen.size());
                }
                fmt::print(stderr, "\n");
                const size_t first = rows.size();
                finishRows(fmt::format("{} seed {} @{:.0f} cm", scene, seed, voxel * 100), vs, truth);
                if (no_quality) continue;
                const auto gt = cloud.build();
                std::vector<Eigen::Vector3d> points(gt.size());
                std::vector<uint32_t> labels(gt.size());
                for (size_t i = 0; i < gt.size(); ++i)
                {
                    points[i] = gt[i].position.cast<double>();
                    labels[i] = gt[i].label;
                }
                const eval::Benchmark bench = eval::Benchmark::nyuv2_40();
                for (size_t k = 0; k < vs.size(); ++k)
                {
                    const PanopticMap& map = *vs[k].map;
                    map.finalize();
                    eval::PanopticEvaluator e3(bench), e2(bench);
                    eval::evaluatePoints(map, points, labels, e3);
                    // 2D at the true poses: a map built at wrong poses shows its misplacement.
                    for (const View& w : views) eval::evaluateView(map, w.T, gen.camera().K, w.sem, w.ins, e2);
                    const auto r3 = e3.result(), r2 = e2.result();
                    rows[first + k].miou3 = 100 * r3.semantic.miou;
                    rows[first + k].pq3 = 100 * r3.pq.all.pq;
                    rows[first + k].pq2 = 100 * r2.pq.all.pq;
                }
            }
        printRows(rows, !no_quality);
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-refine-bench: {}\n", e.what());
        return 1;
    }
    return 0;
}
