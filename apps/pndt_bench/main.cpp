// pndt-bench: frames/s and time per stage of the full panoptic update (1 and N
// threads), side by side with OctoMap (default insert and lazy_eval+discretize)
// and MRPT's COctoMap (and Bonxai, in a build with it) doing occupancy only, on identical frames; bytes
// per mapped voxel, peak RSS, and the ratios the speed targets are stated in.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <mrpt/maps/COctoMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <octomap/octomap.h>
#include <pndt/panoptic_map.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <thread>
#ifdef __linux__
#include <pthread.h>
#include <sched.h>
#endif

#include "bench_frames.h"
#include "bonxai_run.h"
#include "carrier_run.h"

using namespace pndt;
using Clock = std::chrono::steady_clock;

namespace
{
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

size_t statusKb(const char* key)
{
    std::ifstream f("/proc/self/status");
    std::string line;
    const size_t n = std::strlen(key);
    while (std::getline(f, line))
        if (line.compare(0, n, key) == 0) return size_t(std::stoul(line.substr(n)));
    return 0;
}
/// Resets the peak RSS (VmHWM) to the current RSS; false if the kernel refuses.
bool resetPeakRss()
{
    std::ofstream f("/proc/self/clear_refs");
    f << "5";
    return bool(f.flush());
}

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

/// FNV-1a over the whole map state, to show that thread counts give the same map.
struct Fnv
{
    uint64_t h = 1469598103934665603ull;
    void bytes(const void* p, size_t n)
    {
        const auto* c = static_cast<const uint8_t*>(p);
        for (size_t i = 0; i < n; ++i) h = (h ^ c[i]) * 1099511628211ull;
    }
    template <typename T>
    void value(const T& v)
    {
        bytes(&v, sizeof(v));
    }
};
uint64_t stateHash(const PanopticMap& m)
{
    Fnv f;
    const auto keys = m.voxels().packedKeys();
    f.bytes(keys.data(), keys.size() * sizeof(uint64_t));
    f.bytes(m.voxels().voxels().data(), m.voxels().size() * sizeof(Voxel));
    f.bytes(m.surfaceRecords().data(), m.surfaceRecords().size() * sizeof(SurfaceRecord));
    for (const LabelRecord& r : m.labelRecords())
    {
        f.bytes(r.semantic.ids, sizeof(r.semantic.ids));
        for (int j = 0; j < LabelRecord::kSemanticCapacity; ++j) f.value(r.semantic.weight(j));
        f.value(r.n_l);
        f.value(r.instances);
    }
    for (const InstanceRecord& r : m.instanceRecords())
    {
        f.bytes(r.hist.ids, sizeof(r.hist.ids));
        for (int j = 0; j < InstanceHistogram::kCapacity; ++j) f.value(r.hist.weight(j));
        f.value(r.n_z);
    }
    f.value(m.nextInstanceId());
    return f.h;
}

/// How much faster `loop(n)` runs as `threads` threads doing n / threads each
/// than as one thread doing n, right now.
template <class Loop>
double parallelSpeedup(int threads, uint64_t n, Loop loop)
{
    volatile uint64_t sink = 0;
    auto t0 = Clock::now();
    sink = sink + loop(n);
    const double one = since(t0);
    t0 = Clock::now();
    std::vector<std::thread> pool;
    std::vector<uint64_t> out(static_cast<size_t>(threads), 0);
    for (int i = 0; i < threads; ++i) pool.emplace_back([&, i] { out[size_t(i)] = loop(n / uint64_t(threads)); });
    for (auto& t : pool) t.join();
    const double many = since(t0);
    for (uint64_t v : out) sink = sink + v;
    return one / many;
}

/// The ceiling for any multi-threaded speed-up on a machine shared with other
/// work, for three kinds of trivially parallel loops: a dependent multiply chain
/// (latency-bound: scales even on two hyper-threads of one core), eight
/// independent chains (throughput-bound: scales only on separate cores) and
/// random reads in a 4 MB table (the size of a 10 cm map's hot data).
struct Ceilings
{
    double chain = 1, independent = 1, random_reads = 1;
    std::string text() const
    {
        return fmt::format("dependent chain x{:.2f}, independent chains x{:.2f}, random reads in 4 MB x{:.2f}", chain,
                           independent, random_reads);
    }
};

Ceilings parallelCeilings(int threads)
{
    constexpr uint64_t kA = 6364136223846793005ull, kC = 1442695040888963407ull;
    Ceilings c;
    if (threads < 2) return c;
    c.chain = parallelSpeedup(threads, 200'000'000, [](uint64_t n) {
        uint64_t x = 1;
        for (uint64_t i = 0; i < n; ++i) x = x * kA + kC;
        return x;
    });
    c.independent = parallelSpeedup(threads, 400'000'000, [](uint64_t n) {
        uint64_t a[8] = {1, 2, 3, 4, 5, 6, 7, 8};
        for (uint64_t i = 0; i < n / 8; ++i)
            for (uint64_t& x : a) x = x * kA + kC;
        return a[0] ^ a[1] ^ a[2] ^ a[3] ^ a[4] ^ a[5] ^ a[6] ^ a[7];
    });
    std::vector<uint32_t> table(1u << 20);
    for (size_t i = 0; i < table.size(); ++i) table[i] = uint32_t(i * 2654435761u);
    c.random_reads = parallelSpeedup(threads, 100'000'000, [&table](uint64_t n) {
        uint64_t x = 12345, sum = 0;
        for (uint64_t i = 0; i < n; ++i)
        {
            x = x * kA + 1;
            sum += table[(x >> 40) & (table.size() - 1)];
        }
        return sum;
    });
    return c;
}

struct PanopticRun
{
    double seconds = 0;      ///< all frames + final propagation
    double propagation = 0;  ///< the final propagation alone
    FrameStats st;
    std::vector<double> frame_seconds;  ///< each frame's integrate() (wall clock)
    std::vector<FrameStats> frame_stats;
    size_t voxels = 0, occupied = 0, bricks = 0, surfaces = 0, labels = 0, instances = 0;
    PanopticMap::MemoryUse mem;
    size_t rss_before_kb = 0;  ///< RSS before the run (the frames are in memory)
    size_t rss_peak_kb = 0;    ///< peak RSS during the run (0: the kernel cannot reset the peak)
    uint64_t hash = 0;
};

PanopticRun runPanoptic(const bench::BenchFrames& b, const MapOptions& o)
{
    PanopticRun r;
    const size_t rss0 = statusKb("VmRSS:");
    const bool rss_ok = resetPeakRss();
    {
        PanopticMap map(o);
        r.frame_seconds.resize(b.frames.size());
        r.frame_stats.resize(b.frames.size());
        const auto t0 = Clock::now();
        for (size_t i = 0; i < b.frames.size(); ++i)
        {
            const auto tf = Clock::now();
            r.frame_stats[i] = map.integrate(b.frames[i], b.poses[i]);
            r.frame_seconds[i] = since(tf);
        }
        const auto t1 = Clock::now();
        for (const FrameStats& f : r.frame_stats) r.st += f;
        map.finalize();  // label propagation is part of the job
        r.propagation = since(t1);
        r.seconds = since(t0);
        r.voxels = map.voxels().size();
        r.occupied = map.occupiedCount();
        r.bricks = map.voxels().brickCount();
        r.surfaces = map.surfaceRecords().size();
        r.labels = map.labelRecords().size();
        r.instances = map.instanceRecords().size();
        r.mem = map.memoryUse();
        r.hash = stateHash(map);
    }
    r.rss_before_kb = rss0;
    r.rss_peak_kb = rss_ok ? statusKb("VmHWM:") : 0;
    return r;
}

/// Which run stands for a measurement: the median run, the fastest run, or
/// each frame's fastest run (frame-min). Every run integrates the same frames
/// into the same map, so frame i costs the same work in each; a neighbour's
/// burst on the shared machine slows a few frames of one run. The fastest run
/// still carries the bursts it had; each frame's minimum over the runs drops
/// those frames, for the 1-thread, N-thread and OctoMap runs alike.
enum class Stat
{
    Median,
    Min,
    FrameMin
};
Stat g_stat = Stat::Median;

/// The run built from each frame's fastest run: its time is the sum of those
/// frames' times and the fastest propagation, its stage times those frames'.
PanopticRun frameMinimum(const std::vector<PanopticRun>& runs)
{
    PanopticRun best = runs.front();
    best.st = FrameStats{};
    double total = 0;
    for (size_t i = 0; i < best.frame_seconds.size(); ++i)
    {
        const PanopticRun* fastest = &runs.front();
        for (const PanopticRun& r : runs)
            if (r.frame_seconds[i] < fastest->frame_seconds[i]) fastest = &r;
        total += fastest->frame_seconds[i];
        best.st += fastest->frame_stats[i];
    }
    for (const PanopticRun& r : runs) best.propagation = std::min(best.propagation, r.propagation);
    best.seconds = total + best.propagation;
    return best;
}

struct Measured
{
    std::vector<PanopticRun> runs;  // sorted by time
    PanopticRun frame_min;
    const PanopticRun& median() const
    {
        return g_stat == Stat::FrameMin ? frame_min : g_stat == Stat::Min ? runs.front() : runs[runs.size() / 2];
    }
    double fps(size_t frames) const { return double(frames) / median().seconds; }
    /// The other statistics, for the log line.
    std::string others(size_t frames) const
    {
        return fmt::format("median run {:.2f}, fastest run {:.2f}, each frame's fastest {:.2f} frames/s",
                           double(frames) / runs[runs.size() / 2].seconds, double(frames) / runs.front().seconds,
                           double(frames) / frame_min.seconds);
    }
};

void sortRuns(Measured& m)
{
    std::sort(m.runs.begin(), m.runs.end(), [](const PanopticRun& a, const PanopticRun& c) { return a.seconds < c.seconds; });
    m.frame_min = frameMinimum(m.runs);
}

Measured measurePanoptic(const bench::BenchFrames& b, const MapOptions& o, int repeat)
{
    Measured m;
    for (int i = 0; i < repeat; ++i) m.runs.push_back(runPanoptic(b, o));
    sortRuns(m);
    return m;
}

/// One measurement per thread count, their runs interleaved (1, 2, 1, 2, ...),
/// and after each round `also()` (the occupancy mappers' runs): on a shared
/// machine all then see the same neighbours, which matters for their ratios
/// more than for any one of them.
std::vector<Measured> measureThreadCounts(const bench::BenchFrames& b, MapOptions o, const std::vector<int>& threads,
                                          int repeat, const std::function<void()>& also)
{
    std::vector<Measured> ms(threads.size());
    for (int i = 0; i < repeat; ++i)
    {
        for (size_t k = 0; k < threads.size(); ++k)
        {
            o.threads = threads[k];
            ms[k].runs.push_back(runPanoptic(b, o));
        }
        if (also) also();
    }
    for (Measured& m : ms) sortRuns(m);
    return ms;
}

using OctoRun = bench::OccupancyRun;  // frame_seconds: cloud + insert; finish: updateInnerOccupancy

/// Occupancy-only runs under the statistic PanopticNDT's runs are reported in.
struct OccupancyStat
{
    double fps = 0, median_fps = 0, fastest_fps = 0, frame_min_fps = 0;
};

OccupancyStat occupancyStat(const std::vector<OctoRun>& runs, double frames)
{
    OccupancyStat st;
    std::vector<double> fps;
    for (const OctoRun& r : runs) fps.push_back(r.fps);
    double frame_min = 0, finish = runs.front().finish_seconds;
    for (size_t i = 0; i < runs.front().frame_seconds.size(); ++i)
    {
        double f = runs.front().frame_seconds[i];
        for (const OctoRun& r : runs) f = std::min(f, r.frame_seconds[i]);
        frame_min += f;
    }
    for (const OctoRun& r : runs) finish = std::min(finish, r.finish_seconds);
    st.frame_min_fps = frames / (frame_min + finish);
    st.median_fps = median(fps);
    st.fastest_fps = *std::max_element(fps.begin(), fps.end());
    st.fps = g_stat == Stat::FrameMin ? st.frame_min_fps : g_stat == Stat::Min ? st.fastest_fps : st.median_fps;
    return st;
}

OctoRun benchOctomap(const bench::BenchFrames& b, double voxel, double max_range, bool fast)
{
    octomap::OcTree tree(voxel);
    OctoRun r = bench::timeFrames(
        b,
        [&](size_t i) {
            octomap::Pointcloud cloud;
            cloud.reserve(b.world_points[i].size());
            for (const auto& p : b.world_points[i]) cloud.push_back(p.x(), p.y(), p.z());
            const Eigen::Vector3d o = b.poses[i].translation();
            tree.insertPointCloud(cloud, octomap::point3d(float(o.x()), float(o.y()), float(o.z())), max_range,
                                  /*lazy_eval=*/fast, /*discretize=*/fast);
        },
        [&] {
            if (fast) tree.updateInnerOccupancy();
        });
    r.cells = tree.getNumLeafNodes();
    r.bytes_per_cell = double(tree.memoryUsage()) / double(std::max<size_t>(1, r.cells));
    return r;
}

double benchMrptOctomap(const bench::BenchFrames& b, double voxel)
{
    mrpt::maps::COctoMap map(voxel);
    const auto t0 = Clock::now();
    for (size_t i = 0; i < b.frames.size(); ++i)
    {
        mrpt::maps::CSimplePointsMap pts;
        pts.reserve(b.world_points[i].size());
        for (const auto& p : b.world_points[i]) pts.insertPointFast(p.x(), p.y(), p.z());
        const Eigen::Vector3d o = b.poses[i].translation();
        map.insertPointCloud(pts, float(o.x()), float(o.y()), float(o.z()));
    }
    return double(b.frames.size()) / since(t0);
}

bench::BenchFrames firstFrames(const bench::BenchFrames& b, size_t n)
{
    bench::BenchFrames few;
    n = std::min(n, b.frames.size());
    few.frames.assign(b.frames.begin(), b.frames.begin() + long(n));
    few.poses.assign(b.poses.begin(), b.poses.begin() + long(n));
    few.world_points.assign(b.world_points.begin(), b.world_points.begin() + long(n));
    return few;
}

/// Share of voxels two maps agree on (both occupied, both free, or both unknown),
/// over the voxels either of them knows.
struct Agreement
{
    size_t voxels = 0, differ = 0;
};
Agreement occupancyAgreement(const PanopticMap& a, const PanopticMap& b)
{
    size_t both = 0, same = 0;
    const auto state = [](const PanopticMap& m, uint32_t i) { return i == kNoRecord ? 0 : (m.voxels()[i].occ > 0 ? 1 : 2); };
    for (uint32_t i = 0; i < a.voxels().size(); ++i)
    {
        const uint32_t j = b.voxels().find(a.voxels().key(i));
        ++both;
        same += state(a, i) == state(b, j);
    }
    for (uint32_t j = 0; j < b.voxels().size(); ++j)
        if (a.voxels().find(b.voxels().key(j)) == kNoRecord) ++both;
    return {both, both - same};
}

/// The widest vector kernels the map's stages pick on this CPU (and a cap set by
/// PNDT_PROJECTION_KERNEL): results of different machines are only comparable with it.
std::string simdText()
{
    std::string text = "scalar";
#if defined(__x86_64__) && defined(__GNUC__)
    __builtin_cpu_init();
    text = __builtin_cpu_supports("avx512f") ? "AVX-512 F" : __builtin_cpu_supports("avx2") ? "AVX2" : "SSE2";
#endif
    if (const char* cap = std::getenv("PNDT_PROJECTION_KERNEL")) text += fmt::format(", capped at {}", cap);
    return text + " kernels";
}

/// p50 / p99 / max of per-frame times, in ms.
std::string latencyText(std::vector<double> seconds)
{
    if (seconds.empty()) return "no frames";
    std::sort(seconds.begin(), seconds.end());
    const auto at = [&](double q) { return 1e3 * seconds[std::min(seconds.size() - 1, size_t(q * double(seconds.size())))]; };
    return fmt::format("p50 {:.2f} ms, p99 {:.2f} ms, max {:.2f} ms", at(0.5), at(0.99), 1e3 * seconds.back());
}

struct Summary
{
    std::string res;
    double voxel;
    std::vector<std::pair<int, Measured>> pndt;  // by thread count
    double octo_fast = 0, octo_default = 0, mrpt = 0;
    size_t octo_leaves = 0;
    double octo_bytes = 0;
    double bonxai = 0;  ///< frames/s, in a build with Bonxai
    size_t bonxai_cells = 0;
    double bonxai_bytes = 0;
};

/// "WxH" with both positive.
bool parseResolution(const std::string& text, int& w, int& h)
{
    return std::sscanf(text.c_str(), "%dx%d", &w, &h) == 2 && w > 0 && h > 0;
}

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"pndt-bench: PanopticNDT vs OctoMap speed and memory on identical synthetic frames"};
    int frames = 20, octomap_frames = 8, mrpt_frames = 4, repeat = 3;
    double label_noise = 0.0;
    std::vector<double> voxels = {0.05, 0.10, 0.20};
    std::vector<std::string> resolutions = {"640x480", "1024x768"};
    std::vector<int> threads = {1, 0};
    bool no_octomap_default = false, no_mrpt = false, no_bonxai = false, only_panoptic = false, ablations = false,
         pin = false, carriers = false;
    std::string markdown, stat = "median", recording;
    app.add_option("-n,--frames", frames, "frames per run")->capture_default_str();
    app.add_option("--repeat", repeat, "runs per measurement (the thread counts' and OctoMap's runs alternate; --stat picks the one reported)")->capture_default_str();
    app.add_option("--threads", threads, "thread counts for PanopticNDT (0 = all cores); the first is the reference")
        ->capture_default_str();
    app.add_option("--octomap-default-frames", octomap_frames, "frames for OctoMap's slow default insert")
        ->capture_default_str();
    app.add_option("--mrpt-frames", mrpt_frames, "frames for MRPT's (slow) COctoMap")->capture_default_str();
    app.add_option("--voxel", voxels, "voxel sizes (m)")->capture_default_str();
    app.add_option("--resolution", resolutions, "WxH")->capture_default_str();
    app.add_option("--recording", recording,
                   "also (without --resolution: only) real depth and poses from this Redwood / TUM folder, "
                   "frames spread over it, with grid labels (wall, floor, 24 things, new ids every frame)");
    app.add_flag("--skip-octomap-default", no_octomap_default, "skip OctoMap's default insert (slow)");
    app.add_flag("--skip-mrpt", no_mrpt, "skip MRPT's COctoMap (slow)");
    app.add_flag("--skip-bonxai", no_bonxai,
                 bench::haveBonxai() ? "skip Bonxai" : "skip Bonxai (this build has none: -DPNDT_BONXAI_DIR)");
    app.add_flag("--only-panoptic", only_panoptic, "PanopticNDT only (for profiling)");
    app.add_flag("--ablations", ablations,
                 "also: cube voxels (w/o NDT), and per-pixel rays with the agreement of merged rays to them");
    app.add_option("--markdown", markdown, "also write the summary table to this file");
    app.add_option("--label-noise", label_noise,
                   "probability per frame that a segment takes a wrong class / an instance splits (0 = perfect labels)")
        ->capture_default_str();
    app.add_option("--stat", stat,
                   "which run stands for a measurement: median (default), min (the fastest run) or frame-min (each "
                   "frame's fastest run: drops a shared machine's bursts)")
        ->check(CLI::IsMember({"median", "min", "frame-min"}));
    app.add_flag("--pin", pin,
                 "pin this thread to CPU 0 and PanopticNDT's workers to CPUs 1.. (for schedulers that keep a "
                 "process on one CPU)");
    app.add_flag("--carriers", carriers,
                 "only time what pndt-map and pndt-live do around the map update: range scan to depth, the label "
                 "images' decode and encode, at each --resolution (--repeat runs, the fastest reported)");
    CLI11_PARSE(app, argc, argv);
    repeat = std::max(1, repeat);
    if (carriers)
    {
        for (const std::string& res : resolutions)
        {
            int w = 0, h = 0;
            if (!parseResolution(res, w, h)) return fmt::print(stderr, "bad resolution {}\n", res), 1;
            bench::runCarriers(w, h, std::max(repeat, 50));
        }
        return 0;
    }
    g_stat = stat == "frame-min" ? Stat::FrameMin : stat == "min" ? Stat::Min : Stat::Median;
#ifdef __linux__
    if (pin)
    {
        cpu_set_t set;
        CPU_ZERO(&set);
        CPU_SET(0, &set);
        pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
    }
#endif

    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string cpu, line;
    while (std::getline(cpuinfo, line))
        if (line.rfind("model name", 0) == 0)
        {
            cpu = line.substr(line.find(':') + 2);
            break;
        }
    fmt::print("pndt-bench: {} frames per run, {} runs per measurement, statistic {}; {} hardware threads ({}, {}); "
               "label noise {}\n",
               frames, repeat, stat, std::thread::hardware_concurrency(), cpu, simdText(), label_noise);
    const int all = int(std::max(1u, std::thread::hardware_concurrency()));
    const Ceilings ceiling_before = parallelCeilings(all);
    fmt::print("parallel ceiling now ({} threads vs 1): {}\n", all, ceiling_before.text());

    std::vector<Summary> summaries;
    std::vector<std::string> inputs = resolutions;
    if (!recording.empty()) inputs = app.count("--resolution") ? resolutions : std::vector<std::string>{};
    if (!recording.empty()) inputs.push_back("recording");
    for (const std::string& input : inputs)
    {
        int w = 0, h = 0;
        bench::BenchFrames b;
        std::string res = input;
        double max_range = 10.0;
        if (input == "recording")
        {
            b = bench::makeRecordingFrames(recording, frames, max_range, label_noise);
            w = b.frames.front().K.width;
            h = b.frames.front().K.height;
            res = fmt::format("{}x{} real depth ({})", w, h, std::filesystem::path(recording).filename().string());
        }
        else
        {
            if (!parseResolution(res, w, h)) return fmt::print(stderr, "bad resolution {}\n", res), 1;
            max_range = w >= 1024 ? 20.0 : 10.0;
            b = bench::makeRoomFrames(frames, w, h, max_range, label_noise);
        }
        const double n = double(b.frames.size());
        for (double v : voxels)
        {
            fmt::print("\n== {} @ {:.2f} m (max range {} m) ==\n", res, v, max_range);
            Summary sum;
            sum.res = res;
            sum.voxel = v;
            MapOptions o;
            o.voxel_size = v;
            o.max_range = max_range;
            o.pin_threads = pin;
            uint64_t hash1 = 0;
            // OctoMap's (and Bonxai's) runs alternate with ours.
            const bool bonxai = !only_panoptic && bench::haveBonxai() && !no_bonxai;
            std::vector<OctoRun> runs, bruns;
            const auto occupancyRuns = [&] {
                if (only_panoptic) return;
                runs.push_back(benchOctomap(b, v, max_range, true));
                if (bonxai) bruns.push_back(bench::runBonxai(b, v, max_range));
            };
            std::vector<Measured> per_count = measureThreadCounts(b, o, threads, repeat, occupancyRuns);
            for (size_t k = 0; k < threads.size(); ++k)
            {
                o.threads = threads[k];
                Measured& m = per_count[k];
                const PanopticRun& r = m.median();
                const FrameStats& st = r.st;
                const double ms = 1e3 / n;
                fmt::print(
                    "PanopticNDT full panoptic, {} thread(s): {:7.2f} frames/s | ms/frame: projection {:.2f}, "
                    "ray/occupancy {:.2f}, NDT {:.2f}, back-projection+matching {:.2f}, histograms {:.2f}; "
                    "propagation {:.1f} ms once | {} rays, {:.0f} ray steps, {} hit voxels /frame\n",
                    o.resolvedThreads(), m.fps(b.frames.size()), ms * st.seconds_projection, ms * st.seconds_occupancy,
                    ms * st.seconds_ndt, ms * st.seconds_matching, ms * st.seconds_histograms, 1e3 * r.propagation,
                    st.rays / b.frames.size(), double(st.ray_steps) / n, st.hit_voxels / b.frames.size());
                fmt::print("    {}\n", m.others(b.frames.size()));
                fmt::print("    frame latency (this run): {}\n", latencyText(r.frame_seconds));
                if (o.resolvedThreads() > 1)
                {
                    // Where the threads' time goes: short of x threads vs one thread by
                    // idle time (waiting, serial parts) or by more work than one thread did.
                    const double caller = 1e3 * (r.seconds - r.propagation) / n;
                    const double waiting = ms * st.seconds_caller_waiting, workers = ms * st.seconds_workers_busy;
                    const double busy = caller - waiting + workers;
                    std::string vs_one;
                    if (k > 0 && sum.pndt.front().first == 1)
                    {
                        const PanopticRun& one = sum.pndt.front().second.median();
                        const double one_ms = 1e3 * (one.seconds - one.propagation) / n;
                        vs_one = fmt::format("; busy x{:.2f} the one-thread frame's {:.2f} ms", busy / one_ms, one_ms);
                    }
                    fmt::print(
                        "    thread time per frame: caller {:.2f} ms ({:.2f} of it waiting for workers), workers busy "
                        "{:.2f}; busy {:.2f}, idle {:.2f} of {} x {:.2f}{}\n",
                        caller, waiting, workers, busy, o.resolvedThreads() * caller - busy, o.resolvedThreads(),
                        caller, vs_one);
                }
                const auto& mu = r.mem;
                const double vox = double(std::max<size_t>(1, r.voxels));
                fmt::print(
                    "    {} voxels ({} occupied), {:.1f} B/voxel (voxels+index {:.1f}, surfaces {:.1f}, labels {:.1f}, "
                    "instances {:.1f}, propagation {:.1f}); {} bricks ({:.0f}% full), {} surface, {} label, {} instance "
                    "records; RSS {:.0f} MB before the run (frames), peak {:.0f} MB during it; state hash {:016x}\n",
                    r.voxels, r.occupied, double(mu.total()) / vox, mu.voxels / vox, mu.surfaces / vox,
                    mu.labels / vox, mu.instances / vox, mu.propagation / vox, r.bricks,
                    100.0 * vox / double(std::max<size_t>(1, r.bricks * VoxelStore::kBrickSlots)), r.surfaces, r.labels,
                    r.instances, r.rss_before_kb / 1024.0, r.rss_peak_kb / 1024.0, r.hash);
                if (hash1 == 0)
                    hash1 = r.hash;
                else if (r.hash != hash1)
                    fmt::print("    WARNING: the map differs from the first thread count's\n");
                sum.pndt.emplace_back(o.resolvedThreads(), std::move(m));
            }
            if (ablations)
            {
                MapOptions c = o;
                c.threads = 1;
                c.use_ndt = false;
                const Measured cube = measurePanoptic(b, c, 1);
                fmt::print("PanopticNDT w/o NDT (cube voxels), 1 thread: {:.2f} frames/s\n", cube.fps(b.frames.size()));
                MapOptions p = o;
                p.threads = 1;
                p.ray_mode = RayMode::PerPixel;
                PanopticMap exact(p), merged(o);
                const auto t0 = Clock::now();
                for (size_t i = 0; i < b.frames.size(); ++i) exact.integrate(b.frames[i], b.poses[i]);
                const double secs = since(t0);
                for (size_t i = 0; i < b.frames.size(); ++i) merged.integrate(b.frames[i], b.poses[i]);
                const Agreement ag = occupancyAgreement(merged, exact);
                fmt::print(
                    "PanopticNDT per-pixel rays, 1 thread: {:.2f} frames/s; merged rays disagree with it on {} of {} "
                    "voxels ({:.3f}%; occupied/free/unknown); occupied voxels {} merged vs {} per-pixel\n",
                    n / secs, ag.differ, ag.voxels, 100.0 * double(ag.differ) / double(std::max<size_t>(1, ag.voxels)),
                    merged.occupiedCount(), exact.occupiedCount());
            }
            if (!only_panoptic)
            {
                const OctoRun& last = runs.back();
                const OccupancyStat fast = occupancyStat(runs, n);
                sum.octo_fast = fast.fps;
                sum.octo_leaves = last.cells;
                sum.octo_bytes = last.bytes_per_cell;
                fmt::print(
                    "OctoMap lazy_eval+discretize: {:7.2f} frames/s | {} leaf nodes, {:.1f} B/node | median run {:.2f}, "
                    "fastest run {:.2f}, each frame's fastest {:.2f} frames/s\n",
                    sum.octo_fast, last.cells, last.bytes_per_cell, fast.median_fps, fast.fastest_fps,
                    fast.frame_min_fps);
                if (bonxai)
                {
                    const OccupancyStat bx = occupancyStat(bruns, n);
                    sum.bonxai = bx.fps;
                    sum.bonxai_cells = bruns.back().cells;
                    sum.bonxai_bytes = bruns.back().bytes_per_cell;
                    fmt::print(
                        "Bonxai ProbabilisticMap: {:7.2f} frames/s | {} cells, {:.1f} B/cell | median run {:.2f}, "
                        "fastest run {:.2f}, each frame's fastest {:.2f} frames/s\n",
                        bx.fps, sum.bonxai_cells, sum.bonxai_bytes, bx.median_fps, bx.fastest_fps, bx.frame_min_fps);
                }
                const auto few = firstFrames(b, size_t(octomap_frames));
                if (!no_octomap_default)
                {
                    sum.octo_default = benchOctomap(few, v, max_range, false).fps;
                    fmt::print("OctoMap insertPointCloud (default), {} frames: {:7.2f} frames/s\n", few.frames.size(),
                               sum.octo_default);
                }
                if (!no_mrpt)
                {
                    const auto fewer = firstFrames(b, size_t(mrpt_frames));
                    sum.mrpt = benchMrptOctomap(fewer, v);
                    fmt::print("MRPT COctoMap, {} frames: {:7.2f} frames/s\n", fewer.frames.size(), sum.mrpt);
                }
            }
            const double one = sum.pndt.front().second.fps(b.frames.size());
            std::string ratios;
            if (sum.octo_fast > 0) ratios += fmt::format("x{:.2f} vs OctoMap fast", one / sum.octo_fast);
            if (sum.octo_default > 0) ratios += fmt::format(", x{:.1f} vs OctoMap default", one / sum.octo_default);
            if (sum.mrpt > 0) ratios += fmt::format(", x{:.1f} vs MRPT COctoMap", one / sum.mrpt);
            if (sum.bonxai > 0) ratios += fmt::format(", x{:.2f} vs Bonxai", one / sum.bonxai);
            for (size_t i = 1; i < sum.pndt.size(); ++i)
                ratios += fmt::format(", {} threads x{:.2f} vs 1", sum.pndt[i].first,
                                      sum.pndt[i].second.fps(b.frames.size()) / one);
            fmt::print("ratios (PanopticNDT, {} thread): {}\n", sum.pndt.front().first, ratios);
            summaries.push_back(std::move(sum));
        }
    }

    // The summary table (markdown): the first thread count against OctoMap, the
    // last against the first.
    const size_t nf = size_t(frames);
    const int t_first = summaries.empty() ? 1 : summaries.front().pndt.front().first;
    const int t_last = summaries.empty() ? 1 : summaries.front().pndt.back().first;
    std::string t = fmt::format("Statistic: {} of {} runs of {} frames.\n\n", stat, repeat, frames);
    t += fmt::format(
        "| frames | voxel | PanopticNDT {0} thr. | PanopticNDT {1} thr. | {1} vs {0} thr. | OctoMap fast | "
        "**PanopticNDT / OctoMap fast** | OctoMap default | PanopticNDT / OctoMap default | MRPT COctoMap | "
        "PanopticNDT / COctoMap | B/voxel | OctoMap B/node | voxels | map MB | peak RSS (frames) |\n",
        t_first, t_last);
    t += "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    const auto opt = [](double v, const char* f) { return v > 0 ? fmt::format(f, v) : std::string("-"); };
    for (const Summary& s : summaries)
    {
        const Measured& m1 = s.pndt.front().second;
        const Measured& mn = s.pndt.back().second;
        const double f1 = m1.fps(nf), fn = mn.fps(nf);
        const auto& r = m1.median();
        t += fmt::format("| {} | {:.0f} cm | {:.1f} | {:.1f} | x{:.2f} | {} | **{}** | {} | {} | {} | {} | {:.1f} | {} | {} | {:.1f} | {:.0f} MB ({:.0f} MB) |\n",
                         s.res, 100 * s.voxel, f1, fn, fn / f1, opt(s.octo_fast, "{:.1f}"),
                         s.octo_fast > 0 ? fmt::format("x{:.2f}", f1 / s.octo_fast) : "-", opt(s.octo_default, "{:.2f}"),
                         s.octo_default > 0 ? fmt::format("x{:.1f}", f1 / s.octo_default) : "-", opt(s.mrpt, "{:.2f}"),
                         s.mrpt > 0 ? fmt::format("x{:.0f}", f1 / s.mrpt) : "-",
                         double(r.mem.total()) / double(std::max<size_t>(1, r.voxels)), opt(s.octo_bytes, "{:.1f}"),
                         r.voxels, double(r.mem.total()) / 1e6, r.rss_peak_kb / 1024.0, r.rss_before_kb / 1024.0);
    }
    t += "\n| frames | voxel | threads | projection | ray/occupancy | NDT | back-projection + matching | histograms | "
         "propagation (once) | total ms/frame |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Summary& s : summaries)
        for (const auto& [th, m] : s.pndt)
        {
            const auto& r = m.median();
            const double ms = 1e3 / double(frames);
            t += fmt::format("| {} | {:.0f} cm | {} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.1f} | {:.2f} |\n",
                             s.res, 100 * s.voxel, th, ms * r.st.seconds_projection, ms * r.st.seconds_occupancy,
                             ms * r.st.seconds_ndt, ms * r.st.seconds_matching, ms * r.st.seconds_histograms,
                             1e3 * r.propagation, ms * r.seconds);
        }
    t += "\nWith more than one thread the workers walk rays while matching and the histograms run: their columns "
         "then hold that overlap, ray/occupancy the rest of the walk and the misses.\n";
    t += "\n| frames | voxel | voxels | occupied | bricks (fill) | B/voxel | voxels + brick index | surface records | "
         "label records | instance records | propagation |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Summary& s : summaries)
    {
        const auto& r = s.pndt.front().second.median();
        const double v = double(std::max<size_t>(1, r.voxels));
        t += fmt::format("| {} | {:.0f} cm | {} | {} | {} ({:.0f}%) | {:.1f} | {:.1f} | {:.1f} ({}) | {:.1f} ({}) | {:.1f} ({}) | {:.1f} |\n",
                         s.res, 100 * s.voxel, r.voxels, r.occupied, r.bricks,
                         100.0 * v / double(std::max<size_t>(1, r.bricks * VoxelStore::kBrickSlots)), r.mem.total() / v,
                         r.mem.voxels / v, r.mem.surfaces / v, r.surfaces, r.mem.labels / v, r.labels,
                         r.mem.instances / v, r.instances, r.mem.propagation / v);
    }
    if (std::any_of(summaries.begin(), summaries.end(), [](const Summary& s) { return s.bonxai > 0; }))
    {
        t += fmt::format("\n| frames | voxel | Bonxai | Bonxai / OctoMap fast | **PanopticNDT {0} thr. / Bonxai** | "
                         "PanopticNDT {1} thr. / Bonxai | Bonxai B/cell |\n|---|---|---|---|---|---|---|\n",
                         t_first, t_last);
        for (const Summary& s : summaries)
            if (s.bonxai > 0)
                t += fmt::format("| {} | {:.0f} cm | {:.1f} | {} | **x{:.2f}** | x{:.2f} | {:.1f} |\n", s.res,
                                 100 * s.voxel, s.bonxai,
                                 s.octo_fast > 0 ? fmt::format("x{:.2f}", s.bonxai / s.octo_fast) : "-",
                                 s.pndt.front().second.fps(nf) / s.bonxai, s.pndt.back().second.fps(nf) / s.bonxai,
                                 s.bonxai_bytes);
    }
    const Ceilings ceiling_after = parallelCeilings(all);
    t += fmt::format("\nParallel ceiling (trivially parallel loops, {} threads vs 1): before the run {}; after it {}.\n",
                     all, ceiling_before.text(), ceiling_after.text());
    fmt::print("\n{}\npeak RSS of the whole run {:.0f} MB\n", t, statusKb("VmHWM:") / 1024.0);
    if (!markdown.empty())
    {
        // Written beside, then renamed: never a half-written table.
        const std::string tmp = markdown + ".tmp";
        std::ofstream f(tmp);
        f << t;
        f.close();
        if (!f || std::rename(tmp.c_str(), markdown.c_str()) != 0)
        {
            std::remove(tmp.c_str());
            return fmt::print(stderr, "cannot write {}\n", markdown), 1;
        }
    }
    return 0;
}
