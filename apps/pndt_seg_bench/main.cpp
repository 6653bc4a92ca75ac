// pndt-seg-bench: how long the segmentation front-end takes per frame (a benchmark, not a test).
//  - post-processing alone: EMSANet-sized tensors (softmax over the classes, centre NMS, offset
//    grouping, Eq. 1 merge) with noisy logits, random centres and offsets;
//  - with --model: the whole front-end (preprocess, OpenCV DNN, post-processing) on the frames of
//    a recording folder (Redwood / TUM layout, --recording) or on a generated frame.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <opencv2/core.hpp>
#include <pndt/io/sequence.h>
#include <pndt/seg/panoptic_postprocess.h>
#include <pndt/seg/segmenter.h>

#include <algorithm>
#include <chrono>
#include <random>

using namespace pndt;
using namespace pndt::seg;

namespace
{
struct Stats
{
    std::vector<double> ms;
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

void benchPostprocess(int W, int H, int C, int centres, int frames, float margin, float noise)
{
    const ClassSet classes = ClassSet::nyuv2_40();
    std::vector<uint16_t> map(static_cast<size_t>(C));
    for (int c = 0; c < C; ++c) map[size_t(c)] = uint16_t(c % int(classes.size()));
    std::mt19937 rng(1);
    std::normal_distribution<float> logit(0.f, noise);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const size_t N = size_t(W) * H;
    std::vector<float> semantic(N * size_t(C)), center(N, 0.f), offset(2 * N);
    // Blocks of one dominant class (as a network's output), noise on every logit.
    for (int c = 0; c < C; ++c)
        for (size_t i = 0; i < N; ++i)
        {
            const size_t x = i % size_t(W), y = i / size_t(W);
            const int dominant = int((x / 64 + 7 * (y / 48)) % size_t(C));
            semantic[size_t(c) * N + i] = logit(rng) + (c == dominant ? margin : 0.f);
        }
    for (int k = 0; k < centres; ++k) center[size_t(u(rng) * float(N - 1))] = 0.2f + 0.8f * u(rng);
    for (auto& o : offset) o = (u(rng) - 0.5f) * 40.f;
    PanopticTensors t;
    t.width = W;
    t.height = H;
    t.classes = C;
    t.semantic = semantic.data();
    t.center = center.data();
    t.offset = offset.data();
    PanopticPostprocessor post(classes, map, {});
    PanopticFrame out;
    post.run(t, out);  // warm-up: allocations happen here only
    Stats s;
    for (int f = 0; f < frames; ++f)
    {
        const auto t0 = std::chrono::steady_clock::now();
        post.run(t, out);
        s.ms.push_back(msSince(t0));
    }
    double mean_sl = 0;
    for (float v : out.semantic_score.data) mean_sl += v;
    fmt::print("post-processing {}x{}, {} classes (winner +{} over N(0, {}) logits: mean S^L {:.3f}), {} centres kept: {}\n",
               W, H, C, margin, noise, mean_sl / double(N), post.centers().size(), s.line());
}

void benchModel(const std::string& model, const std::string& recording, int frames)
{
    const ClassSet classes = ClassSet::nyuv2_40();
    auto seg = loadSegmenter(model, classes);
    fmt::print("front-end: {}\n", seg->describe());
    io::RgbdSequence seq;
    if (!recording.empty())
    {
        seq = std::filesystem::exists(std::filesystem::path(recording) / "rgb.txt") ? io::openTumSequence(recording)
                                                                                   : io::openRedwoodSequence(recording);
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
    int W = 640, H = 480, C = 41, centres = 30, frames = 50;
    std::string model, recording;
    float margin = 6.f, noise = 2.f;
    app.add_option("--width", W, "tensor width")->capture_default_str();
    app.add_option("--height", H, "tensor height")->capture_default_str();
    app.add_option("--classes", C, "semantic channels")->capture_default_str();
    app.add_option("--centres", centres, "centre peaks in the heatmap")->capture_default_str();
    app.add_option("--frames", frames, "frames timed")->capture_default_str();
    app.add_option("--margin", margin, "logit margin of each block's winning class")->capture_default_str();
    app.add_option("--noise", noise, "standard deviation of the logit noise")->capture_default_str();
    app.add_option("--model", model, "also time this model description's whole front-end");
    app.add_option("--recording", recording, "Redwood / TUM folder whose frames the model sees");
    CLI11_PARSE(app, argc, argv);
    try
    {
        cv::setNumThreads(1);
        benchPostprocess(W, H, C, centres, frames, margin, noise);
        if (!model.empty()) benchModel(model, recording, frames);
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-seg-bench: error: {}\n", e.what());
        return 1;
    }
    return 0;
}
