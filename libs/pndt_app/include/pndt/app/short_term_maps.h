// Rolling short-term maps (design §7): every period the current map is
// finalised, written atomically and replaced by a successor that has already
// been warming up, so a consumer never sees an empty map. Writing a finished
// map (archive, PLY, index.json) runs on a background thread, one map at a
// time and in order, so mapping does not stall on the disk at hand-over.
#pragma once

#include <pndt/mrpt/PanopticNDTMap.h>

#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

namespace pndt::app
{
struct ShortTermOptions
{
    double period = 0;              ///< 0: one map for the whole run
    bool period_in_frames = false;  ///< period counts frames instead of sensor seconds
    double warmup = 0.25;           ///< fraction of a period the successor is fed before taking over
    bool stable_ids = true;         ///< successor's instances take their predecessor's ids by voxel overlap
    std::string out_dir = ".";
    std::string prefix = "map";
    bool write_ply = false;
    bool write_files = true;        ///< false: keep maps in memory only (tests, live use)
    /// Also append each map, as a pndt::CObservationPanopticMap stamped with its last
    /// frame's time, to <out_dir>/maps.rawlog (map_rawlog.h; needs write_files).
    bool write_rawlog = false;
    std::string rawlog_label = "PANOPTIC_MAP";  ///< sensorLabel of the maps in maps.rawlog
    /// Maps per rawlog file (map_rawlog.h): 0 = automatic, one maps.rawlog without keep_maps,
    /// keep_maps maps a file (maps-0000.rawlog, ...) with it.
    size_t rawlog_segment_maps = 0;
    /// Size budget of one map in voxels (0 = none): a map that reaches it after a frame is
    /// finalised and written early and the next short-term map takes over (the successor if
    /// one is warming up, else a new map), so a long run never grows one map without bound.
    uint64_t max_voxels = 0;
    /// Map files kept on disk (0 = all): once a new map is written, the oldest beyond the
    /// newest `keep_maps` are deleted (archive and PLY) and index.json lists only those kept,
    /// so a robot that maps all day neither fills its disk with maps nor rewrites an
    /// ever longer index every period. The maps' rawlog is then cut into files
    /// (rawlog_segment_maps) and a file whose maps are all older than the newest
    /// `keep_maps` is deleted: at most keep_maps + one file's maps stay in it.
    size_t keep_maps = 0;
};

/// One written map, as listed in index.json.
struct MapIndexEntry
{
    std::string file;
    double t_start = 0, t_end = 0;
    uint64_t frames = 0;
    size_t voxels = 0, instances = 0;
};

class MapRawlogWriter;

class ShortTermMaps
{
   public:
    using Factory = std::function<PanopticNDTMap::Ptr()>;
    ShortTermMaps(Factory make_map, ShortTermOptions options);
    /// Waits for a map still being written (its error, if any, is lost: call finish()).
    ~ShortTermMaps();
    ShortTermMaps(const ShortTermMaps&) = delete;
    ShortTermMaps& operator=(const ShortTermMaps&) = delete;

    /// Integrates a frame taken at sensor time `t`; may hand over to the next map.
    void integrate(const PanopticFrame& frame, const Pose& T_world_cam, double t);

    /// The map consumers should use now (nullptr before the first frame).
    PanopticNDTMap::Ptr current() const { return current_.map; }
    /// Finalises and writes the current map (end of input, Ctrl-C) and waits
    /// until every map is on disk. Idempotent. A write that failed in the
    /// background is rethrown here or at the next hand-over.
    void finish();

    /// Every map written this run, in order (with keep_maps, the files of those before
    /// firstListedMap() are deleted).
    const std::vector<MapIndexEntry>& index() const { return index_; }
    /// Index of the first map index.json lists (0 unless keep_maps deleted older ones).
    size_t firstListedMap() const { return first_listed_; }
    /// Stats of every frame integrated into any map (warm-up frames count twice).
    const FrameStats& totals() const { return totals_; }
    /// Seconds the mapping thread spent on finished maps: finalising them and
    /// waiting for the previous write (the writing itself runs beside mapping).
    double secondsWriting() const { return seconds_writing_; }
    uint64_t framesSeen() const { return frames_; }
    /// The maps.rawlog writer (write_rawlog), e.g. to interleave input observations
    /// with addInput(); nullptr when off.
    MapRawlogWriter* rawlog() const { return rawlog_.get(); }
    /// Hand-overs forced by ShortTermOptions::max_voxels (not by the period).
    uint64_t budgetHandOvers() const { return budget_hand_overs_; }

    /// Maps the successor's instance ids to its predecessor's by voxel overlap:
    /// a successor instance takes the predecessor instance that holds most of its
    /// voxels, if that is at least half of them.
    static void carryInstanceIds(const PanopticMap& from, PanopticMap& to);
    /// Ids a map may create during one warm-up before blocks could overlap.
    static constexpr uint32_t kIdBlock = 1u << 16;

   private:
    struct Slot
    {
        PanopticNDTMap::Ptr map;
        double t_start = 0, t_end = 0;
        uint64_t frames = 0;
    };
    double clock(double t) const { return options_.period_in_frames ? double(frames_) : t; }
    void startSuccessor(double t);
    void feed(Slot& s, const PanopticFrame& f, const Pose& T, double t);
    void write(const Slot& s);
    std::string plyFile(size_t map) const;
    void waitForWriter();

    Factory make_map_;
    ShortTermOptions options_;
    Slot current_, next_;
    double period_start_ = 0;  ///< clock value at which the current period began
    uint64_t frames_ = 0;
    uint64_t budget_hand_overs_ = 0;
    bool finished_ = false;
    std::vector<MapIndexEntry> index_;
    size_t first_listed_ = 0;  ///< see firstListedMap()
    FrameStats totals_;
    double seconds_writing_ = 0;
    std::future<void> writer_;  ///< the map being written, if any
    std::unique_ptr<MapRawlogWriter> rawlog_;  ///< maps.rawlog, its own writer thread
};

/// For the apps' summaries: "" or " lists the newest K; the N older deleted" (keep_maps).
std::string keptMapsNote(const ShortTermMaps& maps);

/// Before a run: "" or a note that `options.out_dir` already holds map files or maps
/// rawlogs of an earlier run (a glob over map_*.pndt.gz would mix the runs; index.json
/// lists only the new one's, once this run writes a map).
std::string earlierRunNote(const ShortTermOptions& options);

/// Where the maps' rawlog goes: <out_dir>/maps.rawlog (or its numbered segments).
std::string mapsRawlogPath(const ShortTermOptions& options);

/// Before a run: "" or why `path` (an input rawlog, a recording) must not be used with these
/// options: it is the run's own maps rawlog or one of its segments, which the run truncates.
std::string ownOutputProblem(const ShortTermOptions& options, const std::string& path);

}  // namespace pndt::app
