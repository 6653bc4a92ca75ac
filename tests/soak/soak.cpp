// Soak run (issue #23, doc/hardening.md). Three ways:
//  - RAWLOG (default): the rawlog replayed in a loop for --minutes, each lap read through the
//    read-ahead stream and shifted in time so the laps form one long recording, paired into
//    frames and mapped into short-term maps written every --period sensor seconds by the
//    background writer (pndt-map's path); at the end every map file is loaded;
//  - RAWLOG --one-map INI: the same laps into one map that is never replaced, as an MRPT app
//    holds it (a CMultiMetricMap built from the .ini with the PanopticNDTMap plugin, every
//    observation through insertObservation); each sample also prints the map's voxels,
//    instance records, the ids' frames-seen entries and the id counter, and at the end the map
//    is saved and must load back as saved;
//  - --watch PID [--maps DIR]: samples another process (pndt-live on the virtual camera:
//    scripts/soak_live.sh) until it exits, then loads every map file in DIR.
// Samples RSS, file descriptors and threads every --sample seconds; at the end prints the RSS
// slope after warm-up and the fd / thread ranges. Exit 1 when a map does not load (or does not
// load back as saved) or fds / threads grow by more than 2.
// Not a ctest (it runs for an hour): scripts/soak.sh and scripts/soak_live.sh run it.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <pndt/app/read_ahead_stream.h>
#include <pndt/app/short_term_maps.h>
#include <pndt/mrpt/map_files.h>
#include <pndt/mrpt/observation_pairer.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;
using namespace pndt;

namespace
{
struct Sample
{
    double t = 0, rss_mb = 0;
    int fds = 0, threads = 0;
};

/// RSS, threads and open files of the process under `proc` (/proc/self or /proc/PID);
/// nothing once it has exited (gone, or a zombie waiting for its parent).
std::optional<Sample> sampleProcess(const fs::path& proc, double t)
{
    Sample s;
    s.t = t;
    std::ifstream f(proc / "status");
    if (!f) return std::nullopt;
    for (std::string line; std::getline(f, line);)
    {
        std::istringstream in(line);
        std::string key, value;
        in >> key;
        if (key == "State:" && (in >> value) && (value == "Z" || value == "X")) return std::nullopt;
        if (key == "VmRSS:") in >> s.rss_mb, s.rss_mb /= 1024.0;
        if (key == "Threads:") in >> s.threads;
    }
    std::error_code ec;
    for (fs::directory_iterator it(proc / "fd", ec), end; !ec && it != end; it.increment(ec)) ++s.fds;
    return s;
}

Sample sampleSelf(double t) { return *sampleProcess("/proc/self", t); }

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

/// One line per sample: time, what the soak has done so far, then the process's figures.
void printSample(const Sample& s, const std::string& progress)
{
    fmt::print("{:7.0f} s  {}  RSS {:7.1f} MB  fds {:3d}  threads {:2d}\n", s.t, progress, s.rss_mb, s.fds,
               s.threads);
    std::fflush(stdout);
}

/// Prints the figures after warm-up; false when fds or threads grew by more than 2.
bool printFigures(const std::vector<Sample>& samples, double warmup_fraction)
{
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
    if (x.empty()) return fmt::print("no samples after warm-up\n"), false;
    fmt::print("RSS after warm-up ({:.0f}% of the run, {} samples): {:.1f} .. {:.1f} MB, slope {:+.2f} MB/hour; "
               "peak {:.1f} MB\n",
               warmup_fraction * 100, x.size(), rss_min, rss_max, slope(x, y), peak);
    fmt::print("file descriptors after warm-up: {} .. {}; threads: {} .. {}\n", fd_min, fd_max, th_min, th_max);
    return fd_max - fd_min <= 2 && th_max - th_min <= 2;
}

/// Loads each map file (*.pndt.gz); false when one does not load.
bool loadEach(const std::vector<fs::path>& files)
{
    size_t loaded = 0;
    for (const fs::path& p : files)
    {
        try
        {
            (void)loadMapArchive(p.string());
            ++loaded;
        }
        catch (const std::exception& ex)
        {
            fmt::print(stderr, "pndt_soak: {}\n", ex.what());
        }
    }
    fmt::print("map files: {} of {} load\n", loaded, files.size());
    return loaded == files.size();
}

/// The one map of --one-map: what an MRPT app embedding the plugin holds.
struct OneMap
{
    mrpt::maps::CMultiMetricMap maps;
    PanopticNDTMap::Ptr map;

    explicit OneMap(const std::string& ini_path)
    {
        if (!fs::exists(ini_path)) throw std::runtime_error(ini_path + ": no such .ini");
        mrpt::config::CConfigFile ini(ini_path);
        mrpt::maps::TSetOfMetricMapInitializers defs;
        defs.loadFromConfigFile(ini, "MAP");
        maps.setListOfMaps(defs);
        map = maps.mapByClass<PanopticNDTMap>();
        if (!map) throw std::runtime_error(ini_path + ": [MAP] holds no PanopticNDTMap");
    }
    uint64_t frames() const
    {
        return map->insertionStats().frames_with_labels + map->insertionStats().frames_geometry_only;
    }
    /// What grows with the ids a map makes (the frames seen of ids no record holds are dropped
    /// every PanopticMap::kDeadInstanceSweep ids).
    std::string figures() const
    {
        const PanopticMap& m = map->core();
        return fmt::format("voxels {:7d}  instance records {:6d}  frames-seen entries {:6d}  next id {:8d}",
                           m.voxels().size(), m.instanceRecords().size(), m.instanceFrames().size(),
                           m.nextInstanceId());
    }
};

/// Saves the map and loads it back: the same voxels, records, ids and frames seen.
bool saveAndReload(const PanopticNDTMap& map, const std::string& path)
{
    saveArchive(map, path);
    const PanopticNDTMap::Ptr back = loadMapArchive(path);
    const PanopticMap &a = map.core(), &b = back->core();
    const bool same = a.voxels().size() == b.voxels().size() &&
                      a.instanceRecords().size() == b.instanceRecords().size() &&
                      a.nextInstanceId() == b.nextInstanceId() && a.instanceFrames() == b.instanceFrames();
    fmt::print("map file {}: {} ({:.1f} MB)\n", path, same ? "loads back as saved" : "DIFFERS after loading",
               double(fs::file_size(path)) / 1e6);
    return same;
}

struct Options
{
    std::string rawlog, out = "out/soak/maps", one_map_ini, maps_dir;
    double minutes = 60, period = 3, sample_s = 10, warmup_fraction = 0.2;
    int watch_pid = 0;
};

/// The looped replay into short-term maps or one map; returns whether its maps load.
bool replay(const Options& opt, std::vector<Sample>& samples)
{
    fs::remove_all(opt.out);
    app::ShortTermOptions o;
    o.period = opt.period;
    o.out_dir = opt.out;
    o.write_ply = false;
    std::optional<app::ShortTermMaps> short_term;
    std::optional<OneMap> one;
    if (opt.one_map_ini.empty())
        short_term.emplace([] { return PanopticNDTMap::Create(); }, o);
    else
        one.emplace(opt.one_map_ini);
    fs::create_directories(opt.out);
    const auto t0 = std::chrono::steady_clock::now();
    const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    samples.push_back(sampleSelf(0));
    uint64_t frames = 0, laps = 0;
    double offset = 0, lap_length = 0;
    std::vector<PairedFrame> done;
    while (elapsed() < opt.minutes * 60)
    {
        app::ReadAheadStream in(opt.rawlog);
        ObservationPairer pairer;
        mrpt::poses::CPose3D robot;
        double first = -1, last = 0;
        while (auto obs = in.next())
        {
            if (auto p = std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(obs))
                robot = p->pose.getMeanVal();
            else if (one)
            {
                // The laps as one recording: the plugin pairs depth and labels by stamp.
                const double t = mrpt::Clock::toDouble(obs->timestamp);
                if (first < 0) first = t;
                last = std::max(last, t);
                obs->timestamp = mrpt::Clock::fromDouble(1.7e9 + offset + t - first);
                one->maps.insertObservation(*obs, robot);
                frames = one->frames();
            }
            else
                pairer.push(*obs, robot, done);
            for (const PairedFrame& f : done)
            {
                const double t = mrpt::Clock::toDouble(f.stamp);
                if (first < 0) first = t;
                last = t;
                short_term->integrate(f.frame, f.T_world_cam, offset + t - first);
                ++frames;
            }
            done.clear();
            if (elapsed() >= samples.back().t + opt.sample_s)
            {
                samples.push_back(sampleSelf(elapsed()));
                printSample(samples.back(),
                            fmt::format("lap {:4d}  frames {:7d}  {}", laps, frames,
                                        one ? one->figures() : fmt::format("maps {:5d}", short_term->index().size())));
            }
            if (elapsed() >= opt.minutes * 60) break;
        }
        if (in.truncated()) fmt::print(stderr, "pndt_soak: {}\n", in.stopReason());
        lap_length = std::max(lap_length, last - std::max(first, 0.0) + 1.0);
        offset += lap_length;  // the next lap continues the recording's clock
        ++laps;
    }
    if (short_term) short_term->finish();
    if (one) one->map->flushPending();
    samples.push_back(sampleSelf(elapsed()));
    const double minutes = samples.back().t / 60, rate = double(frames) / samples.back().t;
    if (one)
    {
        fmt::print("\nsoak: {:.1f} min, {} laps, {} frames ({:.1f} frames/s) into one map: {}\n", minutes, laps,
                   frames, rate, one->figures());
        return saveAndReload(*one->map, (fs::path(opt.out) / "one_map.pndt.gz").string());
    }
    fmt::print("\nsoak: {:.1f} min, {} laps, {} frames ({:.1f} frames/s), {} maps written\n", minutes, laps, frames,
               rate, short_term->index().size());
    std::vector<fs::path> files;
    for (const auto& e : short_term->index()) files.push_back(fs::path(opt.out) / e.file);
    return loadEach(files);
}

/// The map files (*.pndt.gz) in `dir`, sorted; none when there is no such folder (yet).
std::vector<fs::path> mapFiles(const std::string& dir)
{
    std::vector<fs::path> files;
    if (dir.empty()) return files;
    const std::string suffix = ".pndt.gz";
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    {
        const std::string name = it->path().filename().string();
        if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
            files.push_back(it->path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

/// Bytes of the files in `dir` (maps, PLYs, index, maps' rawlogs): what a run leaves on disk.
uint64_t folderBytes(const std::string& dir)
{
    uint64_t bytes = 0;
    if (dir.empty()) return bytes;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    {
        std::error_code size_ec;  // a file deleted meanwhile counts as gone
        const uint64_t size = it->is_regular_file(size_ec) ? fs::file_size(it->path(), size_ec) : 0;
        if (!size_ec) bytes += size;
    }
    return bytes;
}

/// Samples process `pid` until it exits; then loads the map files in opt.maps_dir.
bool watch(const Options& opt, std::vector<Sample>& samples)
{
    const fs::path proc = fs::path("/proc") / std::to_string(opt.watch_pid);
    const auto t0 = std::chrono::steady_clock::now();
    const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    uint64_t most_bytes = 0;
    for (;;)
    {
        const std::optional<Sample> s = sampleProcess(proc, elapsed());
        if (!s) break;
        samples.push_back(*s);
        const uint64_t bytes = folderBytes(opt.maps_dir);
        most_bytes = std::max(most_bytes, bytes);
        printSample(*s, fmt::format("pid {}  map files {:5d}  on disk {:7.1f} MB", opt.watch_pid,
                                    mapFiles(opt.maps_dir).size(), bytes / 1e6));
        const double next = samples.front().t + opt.sample_s * double(samples.size());
        while (elapsed() < next && fs::exists(proc / "status"))
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    if (samples.size() < 2)
    {
        fmt::print(stderr, "pndt_soak: process {} is not running (or ended before two samples)\n", opt.watch_pid);
        return false;
    }
    fmt::print("\nsoak: process {} watched for {:.1f} min\n", opt.watch_pid, samples.back().t / 60);
    if (opt.maps_dir.empty()) return true;
    const std::vector<fs::path> files = mapFiles(opt.maps_dir);
    fmt::print("{} map files in {}; the folder held {:.1f} MB at most, {:.1f} MB at the end\n", files.size(),
               opt.maps_dir, most_bytes / 1e6, folderBytes(opt.maps_dir) / 1e6);
    return !files.empty() && loadEach(files);
}
}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"pndt_soak: looped rawlog replay into short-term maps or one map, or another process watched; "
                 "RSS / fd / thread figures"};
    Options opt;
    app.add_option("rawlog", opt.rawlog, "rawlog to loop (e.g. from pndt-generate)");
    app.add_option("--minutes", opt.minutes, "wall-clock length of the run");
    app.add_option("--period", opt.period, "short-term map period (sensor seconds)");
    app.add_option("--one-map", opt.one_map_ini,
                   "instead of short-term maps, one map never replaced: a CMultiMetricMap from this .ini "
                   "(e.g. config/panoptic_ndt.ini)");
    app.add_option("--watch", opt.watch_pid, "instead of a replay, sample this process until it exits");
    app.add_option("--maps", opt.maps_dir, "--watch: then load every *.pndt.gz in this folder");
    app.add_option("--sample", opt.sample_s, "seconds between samples");
    app.add_option("--warmup", opt.warmup_fraction, "fraction of the run before the RSS slope is measured");
    app.add_option("-o,--out", opt.out, "output folder (emptied first)");
    CLI11_PARSE(app, argc, argv);
    if (opt.rawlog.empty() == (opt.watch_pid == 0))
    {
        fmt::print(stderr, "pndt_soak: give either a rawlog to replay or --watch PID\n");
        return 2;
    }

    std::vector<Sample> samples;
    bool maps_ok = false;
    try
    {
        maps_ok = opt.watch_pid ? watch(opt, samples) : replay(opt, samples);
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt_soak: {}\n", e.what());
        return 2;
    }
    const bool ok = printFigures(samples, opt.warmup_fraction) && maps_ok;
    fmt::print("{}\n", ok ? "soak: OK" : "soak: FAILED");
    return ok ? 0 : 1;
}
