// Soak run (issue #23, doc/hardening.md): replays a rawlog in a loop for --minutes, each lap
// read through the read-ahead stream and the depth / label pairing, shifted in time so the
// laps form one long recording, into short-term maps written every --period sensor seconds
// by the background writer. Samples RSS, file descriptors and threads of this process every
// --sample seconds; at the end prints the RSS slope after warm-up, the fd / thread ranges,
// and loads every map file written. Exit 1 when a map does not load or fds / threads grow.
// Not a ctest (it runs for an hour): scripts/soak.sh builds and runs it.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <pndt/app/read_ahead_stream.h>
#include <pndt/app/short_term_maps.h>
#include <pndt/mrpt/map_files.h>
#include <pndt/mrpt/observation_pairer.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace pndt;

namespace
{
struct Sample
{
    double t = 0, rss_mb = 0;
    int fds = 0, threads = 0;
    uint64_t frames = 0;
};

Sample sampleSelf(double t, uint64_t frames)
{
    Sample s;
    s.t = t;
    s.frames = frames;
    std::ifstream f("/proc/self/status");
    for (std::string line; std::getline(f, line);)
    {
        std::istringstream in(line);
        std::string key;
        in >> key;
        if (key == "VmRSS:") in >> s.rss_mb, s.rss_mb /= 1024.0;
        if (key == "Threads:") in >> s.threads;
    }
    for ([[maybe_unused]] const auto& e : fs::directory_iterator("/proc/self/fd")) ++s.fds;
    return s;
}

/// Least-squares slope of y over x.
double slope(const std::vector<double>& x, const std::vector<double>& y)
{
    const double n = double(x.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t i = 0; i < x.size(); ++i)
    {
        sx += x[i];
        sy += y[i];
        sxx += x[i] * x[i];
        sxy += x[i] * y[i];
    }
    const double d = n * sxx - sx * sx;
    return d > 0 ? (n * sxy - sx * sy) / d : 0.0;
}
}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"pndt_soak: looped rawlog replay into short-term maps, with RSS / fd / thread figures"};
    std::string rawlog, out = "out/soak/maps";
    double minutes = 60, period = 3, sample_s = 10, warmup_fraction = 0.2;
    app.add_option("rawlog", rawlog, "rawlog to loop (e.g. from pndt-generate)")->required();
    app.add_option("--minutes", minutes, "wall-clock length of the run");
    app.add_option("--period", period, "short-term map period (sensor seconds)");
    app.add_option("--sample", sample_s, "seconds between samples");
    app.add_option("--warmup", warmup_fraction, "fraction of the run before the RSS slope is measured");
    app.add_option("-o,--out", out, "output folder (emptied first)");
    CLI11_PARSE(app, argc, argv);

    fs::remove_all(out);
    app::ShortTermOptions o;
    o.period = period;
    o.out_dir = out;
    o.write_ply = false;
    app::ShortTermMaps maps([] { return PanopticNDTMap::Create(); }, o);
    const auto t0 = std::chrono::steady_clock::now();
    const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    std::vector<Sample> samples{sampleSelf(0, 0)};
    uint64_t frames = 0, laps = 0;
    double offset = 0, lap_length = 0;
    std::vector<PairedFrame> done;
    while (elapsed() < minutes * 60)
    {
        app::ReadAheadStream in(rawlog);
        ObservationPairer pairer;
        mrpt::poses::CPose3D robot;
        double first = -1, last = 0;
        while (auto obs = in.next())
        {
            if (auto p = std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(obs))
                robot = p->pose.getMeanVal();
            else
                pairer.push(*obs, robot, done);
            for (const PairedFrame& f : done)
            {
                const double t = mrpt::Clock::toDouble(f.stamp);
                if (first < 0) first = t;
                last = t;
                maps.integrate(f.frame, f.T_world_cam, offset + t - first);
                ++frames;
            }
            done.clear();
            if (elapsed() >= samples.back().t + sample_s)
            {
                samples.push_back(sampleSelf(elapsed(), frames));
                const Sample& s = samples.back();
                fmt::print("{:7.0f} s  lap {:4d}  frames {:7d}  maps {:5d}  RSS {:7.1f} MB  fds {:3d}  threads {:2d}\n", s.t,
                           laps, frames, maps.index().size(), s.rss_mb, s.fds, s.threads);
                std::fflush(stdout);
            }
            if (elapsed() >= minutes * 60) break;
        }
        if (in.truncated()) fmt::print(stderr, "pndt_soak: {}\n", in.stopReason());
        lap_length = std::max(lap_length, last - std::max(first, 0.0) + 1.0);
        offset += lap_length;  // the next lap continues the recording's clock
        ++laps;
    }
    maps.finish();
    samples.push_back(sampleSelf(elapsed(), frames));

    // Figures after warm-up.
    std::vector<double> x, y;
    int fd_min = 1 << 30, fd_max = 0, th_min = 1 << 30, th_max = 0;
    double rss_min = 1e30, rss_max = 0, peak = 0;
    for (const Sample& s : samples)
    {
        peak = std::max(peak, s.rss_mb);
        if (s.t < warmup_fraction * samples.back().t) continue;
        x.push_back(s.t / 3600.0);
        y.push_back(s.rss_mb);
        fd_min = std::min(fd_min, s.fds), fd_max = std::max(fd_max, s.fds);
        th_min = std::min(th_min, s.threads), th_max = std::max(th_max, s.threads);
        rss_min = std::min(rss_min, s.rss_mb), rss_max = std::max(rss_max, s.rss_mb);
    }
    size_t loaded = 0, failed = 0;
    for (const auto& e : maps.index())
    {
        try
        {
            (void)loadMapArchive((fs::path(out) / e.file).string());
            ++loaded;
        }
        catch (const std::exception& ex)
        {
            ++failed;
            fmt::print(stderr, "pndt_soak: {}\n", ex.what());
        }
    }
    fmt::print("\nsoak: {:.1f} min, {} laps, {} frames ({:.1f} frames/s), {} maps written\n", samples.back().t / 60, laps,
               frames, frames / samples.back().t, maps.index().size());
    fmt::print("RSS after warm-up ({:.0f}% of the run, {} samples): {:.1f} .. {:.1f} MB, slope {:+.2f} MB/hour; "
               "peak {:.1f} MB\n",
               warmup_fraction * 100, x.size(), rss_min, rss_max, slope(x, y), peak);
    fmt::print("file descriptors after warm-up: {} .. {}; threads: {} .. {}\n", fd_min, fd_max, th_min, th_max);
    fmt::print("map files: {} of {} load\n", loaded, maps.index().size());
    const bool ok = failed == 0 && fd_max - fd_min <= 2 && th_max - th_min <= 2;
    fmt::print("{}\n", ok ? "soak: OK" : "soak: FAILED");
    return ok ? 0 : 1;
}
