// pndt-seg-bench: how long the segmentation front-end takes per frame (a benchmark, not a test).
//  - post-processing alone on EMSANet-sized tensors (softmax over the classes, centre NMS, offset
//    grouping, Eq. 1 merge), on two inputs:
//      "scene": network-like outputs made from a generated room's ground truth (pndt_sim): logits
//               at 1/4 resolution with a per-region winning margin, bilinearly upsampled like a
//               network's decoder output (soft, confusable borders), a few uncertain cells,
//               Gaussian centre peaks at the visible objects and offsets pointing to them;
//      "noise": the worst case, iid Gaussian logits over blocks of one dominant class, random
//               centres and offsets;
//    plus the memory floor (one read sweep over the same logits);
//  - with --model: the whole front-end (preprocess, OpenCV DNN, post-processing) on the frames of
//    a recording folder (Redwood / TUM layout, --recording) or on a generated frame.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <pndt/io/sequence.h>
#include <pndt/look_at.h>
#include <pndt/seg/panoptic_postprocess.h>
#include <pndt/seg/segmenter.h>
#include <pndt/sim/indoor_scene.h>
#include <pndt/sim/renderer.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <map>
#include <random>

using namespace pndt;
using namespace pndt::seg;

namespace
{
struct Stats
{
    std::vector<double> ms;
    double min() const { return *std::min_element(ms.begin(), ms.end()); }
    double median() const
    {
        auto v = ms;
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    }
    std::string line() const
    {
        auto v = ms;
        std::sort(v.begin(), v.end());
        double sum = 0;
        for (double x : v) sum += x;
        const auto pct = [&](double p) { return v[std::min(v.size() - 1, size_t(p * double(v.size())))]; };
        return fmt::format("mean {:.2f} ms, p50 {:.2f}, p99 {:.2f}, min {:.2f} ({} frames)", sum / double(v.size()),
                           pct(0.5), pct(0.99), v.front(), v.size());
    }
};

double msSince(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// CPU time of this thread (ms): the post-processing's time on one core even when the machine
/// is shared (wall time would count the time slices other processes get).
double threadMs()
{
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

/// Planar network outputs owned by the benchmark.
struct BenchTensors
{
    int W = 0, H = 0, C = 0;
    std::vector<float> semantic, center, offset;
    std::string what;
    PanopticTensors view(bool instances) const
    {
        return {W, H, C, semantic.data(), instances ? center.data() : nullptr, instances ? offset.data() : nullptr};
    }
};

/// Worst case: iid N(0, noise) on every logit, +margin for the dominant class of 64×48 blocks;
/// `centres` random peaks, uniform offsets in ±20 pixels.
BenchTensors noiseTensors(int W, int H, int C, int centres, float margin, float noise)
{
    BenchTensors b;
    b.W = W;
    b.H = H;
    b.C = C;
    std::mt19937 rng(1);
    std::normal_distribution<float> logit(0.f, noise);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const size_t N = size_t(W) * H;
    b.semantic.resize(N * size_t(C));
    b.center.assign(N, 0.f);
    b.offset.resize(2 * N);
    for (int c = 0; c < C; ++c)
        for (size_t i = 0; i < N; ++i)
        {
            const size_t x = i % size_t(W), y = i / size_t(W);
            const int dominant = int((x / 64 + 7 * (y / 48)) % size_t(C));
            b.semantic[size_t(c) * N + i] = logit(rng) + (c == dominant ? margin : 0.f);
        }
    for (int k = 0; k < centres; ++k) b.center[size_t(u(rng) * float(N - 1))] = 0.2f + 0.8f * u(rng);
    for (auto& o : b.offset) o = (u(rng) - 0.5f) * 40.f;
    b.what = fmt::format("noise: winner +{} over iid N(0, {}) logits, {} random centres, random offsets", margin, noise,
                         centres);
    return b;
}

struct SceneLogitOptions
{
    std::string preset = "living";
    float margin_min = 8.f, margin_max = 15.f;  ///< winner over the runner-up, per region
    /// The other classes: N(runner-up − 2.2·spread, spread) (so the runner-up is about the best of
    /// them), never above the runner-up. 0 = all at the runner-up's level (nothing to skip).
    float spread = 4.f;
    float cell_noise = 0.5f;   ///< N(0, ·) on every logit of every 1/4-resolution cell
    float uncertain = 0.02f;   ///< fraction of cells whose runner-up comes within 0..2 of the winner
};

/// Network-like outputs of a rendered view of a generated room (see the file comment).
BenchTensors sceneTensors(int W, int H, int C, const SceneLogitOptions& o)
{
    if (W % 4 || H % 4) throw InputError("the scene input needs a width and height divisible by 4");
    const sim::Scene scene = sim::makeIndoorScene(sim::indoorScenePreset(o.preset));
    const Eigen::Vector3d lo = scene.room.min(), hi = scene.room.max();
    const Eigen::Vector3d eye(lo.x() + 0.4, lo.y() + 0.5, 1.4), target(hi.x() - 1.0, hi.y() - 1.2, 0.6);
    const double f = 525.0 * W / 640.0;
    const CameraIntrinsics K{W, H, f, f, (W - 1) / 2.0, (H - 1) / 2.0};
    sim::RenderedFrame gt;
    sim::render(scene, lookAt(eye, target), K, gt);
    const size_t N = size_t(W) * H;
    // One region per instance (things) or per class (stuff): its class, margin, class offsets.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::normal_distribution<float> gauss(0.f, 1.f);
    struct Region
    {
        int cls;
        std::vector<float> logit;  ///< per channel, the winner at 0
    };
    std::map<uint64_t, Region> regions;
    const auto regionOf = [&](size_t i) -> Region& {
        const int cls = std::min<int>(gt.semantic.data[i], C - 1) ? std::min<int>(gt.semantic.data[i], C - 1) : 1;
        const uint64_t key = (uint64_t(gt.instance.data[i]) << 16) | uint64_t(cls);
        auto it = regions.find(key);
        if (it != regions.end()) return it->second;
        Region r{cls, std::vector<float>(size_t(C))};
        const float margin = o.margin_min + (o.margin_max - o.margin_min) * u(rng);
        int runner = int(u(rng) * float(C - 1));
        if (runner >= cls) ++runner;
        for (int c = 0; c < C; ++c)
            r.logit[size_t(c)] = c == cls      ? 0.f
                                 : c == runner ? -margin
                                               : -margin - std::max(0.f, o.spread * (2.2f + gauss(rng)));
        return regions.emplace(key, std::move(r)).first->second;
    };
    // Logits at 1/4 resolution (the cell's centre pixel's region), upsampled bilinearly.
    const int w = W / 4, h = H / 4;
    std::vector<cv::Mat> low(static_cast<size_t>(C));
    for (auto& m : low) m.create(h, w, CV_32F);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
        {
            const Region& r = regionOf(size_t(4 * y + 2) * W + size_t(4 * x + 2));
            const float level = 10.f + 2.f * gauss(rng);  // absolute logits vary; softmax does not care
            const bool unsure = u(rng) < o.uncertain;
            int rival = int(u(rng) * float(C - 1));
            if (rival >= r.cls) ++rival;
            for (int c = 0; c < C; ++c)
            {
                float v = r.logit[size_t(c)];
                if (unsure && c == rival) v = -2.f * u(rng);
                low[size_t(c)].at<float>(y, x) = level + v + o.cell_noise * gauss(rng);
            }
        }
    BenchTensors b;
    b.W = W;
    b.H = H;
    b.C = C;
    b.semantic.resize(N * size_t(C));
    for (int c = 0; c < C; ++c)
    {
        cv::Mat full(H, W, CV_32F, b.semantic.data() + size_t(c) * N);
        cv::resize(low[size_t(c)], full, full.size(), 0, 0, cv::INTER_LINEAR);
    }
    // Instances: Gaussian peaks (σ = 8 px) at the centroids of visible objects of ≥ 400 pixels,
    // offsets (yx) from each thing pixel to its centroid with N(0, 1) noise; stuff: N(0, 2).
    const ClassSet classes = ClassSet::nyuv2_40();
    std::map<uint32_t, std::array<double, 3>> sums;
    for (size_t i = 0; i < N; ++i)
        if (const uint32_t z = gt.instance.data[i]; z && classes.isThing(gt.semantic.data[i]))
        {
            auto& s = sums[z];
            s[0] += double(i % size_t(W));
            s[1] += double(i / size_t(W));
            s[2] += 1;
        }
    std::map<uint32_t, std::array<float, 2>> centroid;
    b.center.assign(N, 0.f);
    int peaks = 0;
    for (const auto& [z, s] : sums)
    {
        const float cx = float(s[0] / s[2]), cy = float(s[1] / s[2]);
        centroid[z] = {cx, cy};
        if (s[2] < 400) continue;
        ++peaks;
        const float peak = 0.5f + 0.5f * u(rng);
        for (int y = std::max(0, int(cy) - 32); y < std::min(H, int(cy) + 33); ++y)
            for (int x = std::max(0, int(cx) - 32); x < std::min(W, int(cx) + 33); ++x)
            {
                const float d2 = (float(x) - cx) * (float(x) - cx) + (float(y) - cy) * (float(y) - cy);
                float& v = b.center[size_t(y) * W + size_t(x)];
                v = std::max(v, peak * std::exp(-d2 / (2.f * 64.f)));
            }
    }
    for (auto& v : b.center) v = std::clamp(v + 0.005f * gauss(rng), 0.f, 1.f);
    b.offset.resize(2 * N);
    size_t things = 0;
    for (size_t i = 0; i < N; ++i)
    {
        const uint32_t z = gt.instance.data[i];
        const auto it = z ? centroid.find(z) : centroid.end();
        float dy = 2.f * gauss(rng), dx = 2.f * gauss(rng);
        if (it != centroid.end())
        {
            ++things;
            dy = it->second[1] - float(i / size_t(W)) + gauss(rng);
            dx = it->second[0] - float(i % size_t(W)) + gauss(rng);
        }
        b.offset[i] = dy;
        b.offset[N + i] = dx;
    }
    b.what = fmt::format(
        "scene '{}': {} regions, {:.0f}% thing pixels, {} centre peaks; winner {}..{} over the runner-up, others "
        "N(runner-up - 2.2 s, s), s = {}, cell noise {}, {:.0f}% uncertain cells, 4x bilinear upsampling",
        o.preset, regions.size(), 100.0 * double(things) / double(N), peaks, o.margin_min, o.margin_max, o.spread,
        o.cell_noise, 100.0 * o.uncertain);
    return b;
}

/// The memory floor: one read sweep over the semantic logits (8 independent sums).
void benchFloor(const BenchTensors& b, int frames)
{
    Stats s;
    float sink = 0;
    for (int f = 0; f < frames; ++f)
    {
        const double t0 = threadMs();
        float acc[16] = {};
        const float* p = b.semantic.data();
        const size_t n = b.semantic.size() & ~size_t(15);
        for (size_t i = 0; i < n; i += 16)
            for (int k = 0; k < 16; ++k) acc[k] += p[i + size_t(k)];
        for (float a : acc) sink += a;
        s.ms.push_back(threadMs() - t0);
    }
    fmt::print("  floor: one read sweep over the {:.0f} MB of logits: min {:.2f} ms, median {:.2f} ({:.3f} ns per "
               "element){}\n",
               double(b.semantic.size()) * 4e-6, s.min(), s.median(), s.min() * 1e6 / double(b.semantic.size()),
               sink == 1.2345f ? " " : "");
}

void benchPostprocess(const BenchTensors& b, int frames, float tolerance, PostprocessOptions::Kernel kernel)
{
    const ClassSet classes = ClassSet::nyuv2_40();
    std::vector<uint16_t> map(static_cast<size_t>(b.C));
    for (int c = 0; c < b.C; ++c) map[size_t(c)] = uint16_t(c % int(classes.size()));
    fmt::print("{}x{}, {} classes, {}\n", b.W, b.H, b.C, b.what);
    struct Variant
    {
        const char* name;
        bool logits, instances;
    };
    const Variant variants[] = {{"max/argmax only (probabilities in)", false, false},
                                {"semantic: argmax + S^L (softmax)", true, false},
                                {"panoptic: + NMS, grouping, merge", true, true}};
    for (const Variant& v : variants)
    {
        PostprocessOptions o;
        o.semantic_is_logit = v.logits;
        o.score_tolerance = tolerance;
        o.kernel = kernel;
        PanopticPostprocessor post(classes, map, o);
        PanopticFrame out;
        const PanopticTensors t = b.view(v.instances);
        post.run(t, out);  // warm-up: allocations happen here only
        Stats s, centres, pixels, merge;
        for (int f = 0; f < frames; ++f)
        {
            const double t0 = threadMs();
            post.run(t, out);
            s.ms.push_back(threadMs() - t0);
            centres.ms.push_back(post.lastTiming().centres_ms);
            pixels.ms.push_back(post.lastTiming().pixels_ms);
            merge.ms.push_back(post.lastTiming().merge_ms);
        }
        double mean_sl = 0;
        for (float x : out.semantic_score.data) mean_sl += x;
        fmt::print("  {:<36}: min {:.2f} ms, median {:.2f} ms ({} frames; mean S^L {:.4f}, {} centres)\n", v.name,
                   s.min(), s.median(), frames, mean_sl / double(out.semantic_score.size()), post.centers().size());
        if (v.instances)
            fmt::print("    stages (min / median ms): centres (NMS) {:.2f} / {:.2f}, pixel pass {:.2f} / {:.2f}, "
                       "merge {:.2f} / {:.2f}\n",
                       centres.min(), centres.median(), pixels.min(), pixels.median(), merge.min(), merge.median());
    }
    benchFloor(b, frames);
}

void benchModel(const std::string& model, const std::string& recording, int frames)
{
    const ClassSet classes = ClassSet::nyuv2_40();
    auto seg = loadSegmenter(model, classes);
    fmt::print("front-end: {}\n", seg->describe());
    io::RgbdSequence seq;
    if (!recording.empty())
    {
        seq = io::openRecordingFolder(recording);
        if (seq.size() == 0) throw InputError(recording + ": no frames");
    }
    Stats pre, net, post, total;
    PanopticFrame out;
    for (int f = 0; f < frames; ++f)
    {
        io::RgbdFrame fr;
        if (!recording.empty())
            fr = seq.load(size_t(f) % seq.size());
        else
        {
            fr.K = {640, 480, 525, 525, 319.5, 239.5};
            fr.depth = Image<float>(640, 480, 2.f);
            fr.color = io::RgbImage(640, 480, {120, 110, 100});
        }
        SegmentationInput in;
        in.depth = &fr.depth;
        in.color = fr.color.empty() ? nullptr : &fr.color;
        in.K = fr.K;
        in.T_world_cam = fr.T_world_cam;
        in.source = recording.empty() ? "generated frame" : fr.id;
        const auto t0 = std::chrono::steady_clock::now();
        seg->segment(in, out);
        total.ms.push_back(msSince(t0));
        pre.ms.push_back(seg->lastTiming().preprocess_ms);
        net.ms.push_back(seg->lastTiming().network_ms);
        post.ms.push_back(seg->lastTiming().postprocess_ms);
    }
    fmt::print("  preprocess     : {}\n  network        : {}\n  post-processing: {}\n  total          : {}\n",
               pre.line(), net.line(), post.line(), total.line());
}
}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"pndt-seg-bench: per-frame time of the segmentation front-end (one thread)"};
    int W = 640, H = 480, C = 41, centres = 30, frames = 30;
    std::string model, recording, input = "both";
    float margin = 6.f, noise = 2.f;
    SceneLogitOptions scene;
    float tolerance = PostprocessOptions{}.score_tolerance;
    app.add_option("--input", input, "post-processing input: scene | noise | both | none")->capture_default_str();
    app.add_option("--width", W, "tensor width")->capture_default_str();
    app.add_option("--height", H, "tensor height")->capture_default_str();
    app.add_option("--classes", C, "semantic channels")->capture_default_str();
    app.add_option("--frames", frames, "frames timed per variant")->capture_default_str()->check(CLI::Range(1, 1000000));
    app.add_option("--centres", centres, "noise input: centre peaks in the heatmap")->capture_default_str();
    app.add_option("--margin", margin, "noise input: logit margin of each block's winning class")->capture_default_str();
    app.add_option("--noise", noise, "noise input: standard deviation of the logit noise")->capture_default_str();
    app.add_option("--scene", scene.preset, "scene input: pndt_sim room preset")->capture_default_str();
    app.add_option("--margin-min", scene.margin_min, "scene input: smallest winning margin")->capture_default_str();
    app.add_option("--margin-max", scene.margin_max, "scene input: largest winning margin")->capture_default_str();
    app.add_option("--spread", scene.spread, "scene input: spread of the other classes below the runner-up")
        ->capture_default_str();
    app.add_option("--uncertain", scene.uncertain, "scene input: fraction of uncertain cells")->capture_default_str();
    std::string kernel_name = "best";
    app.add_option("--kernel", kernel_name, "pixel-pass kernel: best (the CPU's widest), avx2 or scalar")
        ->check(CLI::IsMember({"best", "avx2", "scalar"}))
        ->capture_default_str();
    app.add_option("--score-tolerance", tolerance, "bound on S^L's relative error from skipped classes (0 = none)")
        ->capture_default_str();
    app.add_option("--model", model, "also time this model description's whole front-end");
    app.add_option("--recording", recording, "Redwood / TUM folder whose frames the model sees");
    CLI11_PARSE(app, argc, argv);
    const auto kernel = kernel_name == "avx2"     ? PostprocessOptions::Kernel::Avx2
                        : kernel_name == "scalar" ? PostprocessOptions::Kernel::Scalar
                                                  : PostprocessOptions::Kernel::Best;
    try
    {
        cv::setNumThreads(1);
        if (input == "scene" || input == "both") benchPostprocess(sceneTensors(W, H, C, scene), frames, tolerance, kernel);
        if (input == "noise" || input == "both") benchPostprocess(noiseTensors(W, H, C, centres, margin, noise), frames, tolerance, kernel);
        if (input != "scene" && input != "noise" && input != "both" && input != "none")
            throw InputError("--input must be scene, noise, both or none");
        if (!model.empty()) benchModel(model, recording, frames);
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-seg-bench: error: {}\n", e.what());
        return 1;
    }
    return 0;
}
