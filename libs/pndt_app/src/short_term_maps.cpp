#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <pndt/app/gz_rawlog_file.h>
#include <pndt/app/map_rawlog.h>
#include <pndt/app/short_term_maps.h>
#include <pndt/mrpt/map_files.h>
#include <tsl/robin_map.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>

namespace pndt::app
{
ShortTermMaps::ShortTermMaps(Factory make_map, ShortTermOptions options)
    : make_map_(std::move(make_map)), options_(std::move(options))
{
    if (options_.period < 0) throw std::invalid_argument("short-term map period must be >= 0");
    if (options_.warmup < 0 || options_.warmup >= 1) throw std::invalid_argument("warm-up must be in [0, 1)");
    if (options_.write_files)
    {
        std::error_code ec;
        std::filesystem::create_directories(options_.out_dir, ec);
        if (ec)
            throw io::WriteError(fmt::format("cannot create the output folder '{}': {}", options_.out_dir, ec.message()));
    }
    if (options_.write_files && options_.write_rawlog)
    {
        MapRawlogOptions o;
        o.path = mapsRawlogPath(options_);
        o.sensor_label = options_.rawlog_label;
        o.keep_maps = options_.keep_maps;
        o.segment_maps = options_.rawlog_segment_maps > 0 ? options_.rawlog_segment_maps : options_.keep_maps;
        rawlog_ = std::make_unique<MapRawlogWriter>(o);
    }
}

ShortTermMaps::~ShortTermMaps()
{
    if (writer_.valid()) writer_.wait();
}

void ShortTermMaps::waitForWriter()
{
    if (writer_.valid()) writer_.get();  // rethrows the writer's error
}

void ShortTermMaps::feed(Slot& s, const PanopticFrame& f, const Pose& T, double t)
{
    if (!s.map)
    {
        s.map = make_map_();
        s.t_start = t;
    }
    totals_ += s.map->integrate(f, T);
    s.t_end = t;
    ++s.frames;
}

void ShortTermMaps::integrate(const PanopticFrame& f, const Pose& T, double t)
{
    if (finished_) throw std::logic_error("ShortTermMaps: integrate() after finish()");
    if (frames_ == 0) period_start_ = clock(t);
    const double now = clock(t);
    const double P = options_.period;
    if (P > 0 && now >= period_start_ + P && current_.map)
    {
        // Hand over: the successor has been warming up; the current map is done.
        write(current_);
        if (!next_.map) startSuccessor(t);  // no warm-up (warmup = 0, or a gap in the data)
        if (options_.stable_ids) carryInstanceIds(current_.map->core(), next_.map->core());
        current_ = std::move(next_);
        next_ = Slot{};
        // Periods stay on a fixed grid even when frames are sparse.
        while (now >= period_start_ + P) period_start_ += P;
    }
    if (options_.max_voxels > 0 && current_.map && current_.map->core().voxels().size() >= options_.max_voxels)
    {
        // Size budget reached: written early, the next map takes over with this frame
        // (so no map is ever empty; the period grid stays).
        write(current_);
        if (!next_.map) startSuccessor(t);
        if (options_.stable_ids) carryInstanceIds(current_.map->core(), next_.map->core());
        current_ = std::move(next_);
        next_ = Slot{};
        ++budget_hand_overs_;
    }
    feed(current_, f, T, t);
    if (P > 0 && now >= period_start_ + P * (1.0 - options_.warmup))
    {
        if (!next_.map) startSuccessor(t);
        feed(next_, f, T, t);
    }
    ++frames_;
    if (rawlog_) rawlog_->mappedUpTo(t);  // interleaved inputs up to t may be written
}

void ShortTermMaps::startSuccessor(double t)
{
    next_.map = make_map_();
    next_.t_start = t;
    // Both maps create ids during the warm-up: give the successor its own block
    // so its new ids never collide with ids it may inherit at hand-over.
    if (options_.stable_ids) next_.map->core().reserveInstanceIds(current_.map->core().nextInstanceId() + kIdBlock);
}

void ShortTermMaps::finish()
{
    if (finished_) return;
    finished_ = true;
    if (current_.map) write(current_);
    waitForWriter();
    if (rawlog_) rawlog_->finish();
}

std::string keptMapsNote(const ShortTermMaps& maps)
{
    if (maps.firstListedMap() == 0) return {};
    return fmt::format(" lists the newest {}; the {} older deleted", maps.index().size() - maps.firstListedMap(),
                       maps.firstListedMap());
}

std::string earlierRunNote(const ShortTermOptions& o)
{
    std::error_code ec;
    std::vector<std::string> earlier;
    const std::string head = o.prefix + "_", tail = ".pndt.gz";
    for (std::filesystem::directory_iterator it(o.out_dir, ec), end; !ec && it != end; it.increment(ec))
    {
        const std::string name = it->path().filename().string();
        if (name.size() > head.size() + tail.size() && name.compare(0, head.size(), head) == 0 &&
            name.compare(name.size() - tail.size(), tail.size(), tail) == 0)
            earlier.push_back(name);
    }
    // The maps' rawlogs too: a run with other rawlog options leaves the earlier ones beside it.
    std::vector<std::string> rawlogs = numberedRawlogsOf(mapsRawlogPath(o));
    if (std::filesystem::exists(mapsRawlogPath(o), ec)) rawlogs.insert(rawlogs.begin(), mapsRawlogPath(o));
    if (earlier.empty() && rawlogs.empty()) return {};
    std::sort(earlier.begin(), earlier.end());
    const auto files = [](const std::vector<std::string>& names, const char* what) {
        if (names.empty()) return std::string();
        const auto name = [](const std::string& f) { return std::filesystem::path(f).filename().string(); };
        return fmt::format("{} {} ({}{})", names.size(), what, name(names.front()),
                           names.size() > 1 ? " .. " + name(names.back()) : std::string());
    };
    const std::string maps = files(earlier, "map file(s)"), logs = files(rawlogs, "maps rawlog(s)");
    return fmt::format("{} holds {}{}{} of an earlier run: this run's files replace them by name once it writes a "
                       "map, the rest stay; index.json will then list this run's maps only (a new folder keeps runs "
                       "apart)",
                       o.out_dir, maps, !maps.empty() && !logs.empty() ? " and " : "", logs);
}

std::string mapsRawlogPath(const ShortTermOptions& o)
{
    return (std::filesystem::path(o.out_dir) / "maps.rawlog").string();
}

std::string ownOutputProblem(const ShortTermOptions& o, const std::string& path)
{
    if (!o.write_files || !o.write_rawlog || !sameRawlogFamily(path, mapsRawlogPath(o))) return {};
    return fmt::format("{} is this run's own maps rawlog (or one of its segments): the run would overwrite it; "
                       "give a copy, another name, or another output folder (-o)",
                       path);
}

std::string ShortTermMaps::plyFile(size_t map) const { return fmt::format("{}_{:04d}.ply", options_.prefix, map); }

void ShortTermMaps::write(const Slot& s)
{
    const auto t0 = std::chrono::steady_clock::now();
    // Finalised here: the hand-over reads the propagated labels (carryInstanceIds),
    // and afterwards the writer only reads the map.
    s.map->flushPending();
    s.map->core().finalize();
    MapIndexEntry e;
    e.file = fmt::format("{}_{:04d}.pndt.gz", options_.prefix, index_.size());
    e.t_start = s.t_start;
    e.t_end = s.t_end;
    e.frames = s.frames;
    e.voxels = s.map->core().voxels().size();
    e.instances = s.map->core().instances().size();
    const std::string ply = plyFile(index_.size());
    index_.push_back(e);
    if (rawlog_) rawlog_->addMap(s.map, s.t_start, s.t_end, s.frames, uint32_t(index_.size() - 1));
    if (options_.write_files)
    {
        waitForWriter();  // one map at a time, so index.json only ever lists complete maps
        // Maps beyond keep_maps leave the index first, then their files go (a crash in between
        // leaves a file no index lists, never an index listing a missing file).
        std::vector<std::string> deleted;
        const size_t first = options_.keep_maps > 0 && index_.size() > options_.keep_maps
                                 ? index_.size() - options_.keep_maps
                                 : 0;
        for (; first_listed_ < first; ++first_listed_)
        {
            deleted.push_back(index_[first_listed_].file);
            deleted.push_back(plyFile(first_listed_));
        }
        nlohmann::json j = nlohmann::json::array();
        for (size_t i = first_listed_; i < index_.size(); ++i)
        {
            const auto& x = index_[i];
            j.push_back({{"file", x.file},
                         {"t_start", x.t_start},
                         {"t_end", x.t_end},
                         {"frames", x.frames},
                         {"voxels", x.voxels},
                         {"instances", x.instances}});
        }
        const std::filesystem::path dir(options_.out_dir);
        writer_ = std::async(std::launch::async, [map = s.map, dir, file = e.file, ply, index = j.dump(2),
                                                  write_ply = options_.write_ply, deleted = std::move(deleted)] {
            saveArchive(*map, (dir / file).string());
            if (write_ply) writePly(*map, (dir / ply).string());
            // Listed only once its files are complete.
            io::writeFileAtomically((dir / "index.json").string(), index + "\n");  // checked writes, errno named
            for (const std::string& f : deleted)
            {
                std::error_code ec;
                std::filesystem::remove(dir / f, ec);  // a file already gone is fine
                if (ec)
                    throw io::WriteError(
                        fmt::format("cannot delete the old map file '{}': {}", (dir / f).string(), ec.message()));
            }
        });
    }
    seconds_writing_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void ShortTermMaps::carryInstanceIds(const PanopticMap& from, PanopticMap& to)
{
    from.finalize();
    to.finalize();
    // Votes: successor instance -> predecessor instance -> voxels in common.
    tsl::robin_map<uint32_t, tsl::robin_map<uint32_t, uint32_t>> votes;
    tsl::robin_map<uint32_t, uint32_t> sizes;
    const auto& store = to.voxels();
    for (uint32_t i = 0; i < store.size(); ++i)
    {
        const uint32_t z = to.panopticLabel(i).instance;
        if (z == 0) continue;
        ++sizes[z];
        const uint32_t j = from.voxels().find(store.key(i));
        if (j == kNoRecord) continue;
        const uint32_t old = from.panopticLabel(j).instance;
        if (old != 0) ++votes[z][old];
    }
    tsl::robin_map<uint32_t, uint32_t> rename;
    for (const auto& [z, v] : votes)
    {
        uint32_t best = 0, count = 0;
        for (const auto& [old, n] : v)
            if (n > count || (n == count && old < best))
            {
                best = old;
                count = n;
            }
        if (2 * count >= sizes[z]) rename[z] = best;
    }
    if (rename.empty()) return;
    to.renameInstances([&](uint32_t id) {
        const auto it = rename.find(id);
        return it == rename.end() ? id : it->second;
    });
}

}  // namespace pndt::app
