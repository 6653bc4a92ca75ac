// maps.rawlog: the stream of short-term maps as an MRPT rawlog (issue #21), one
// pndt::CObservationPanopticMap per handed-over map, optionally interleaved with
// the input observations, for MRPT's rawlog tools (rawlog-edit -p, RawLogViewer -l).
//
// Everything is serialised and compressed on the writer's own thread; the caller
// only queues shared pointers. Each object is followed by a zlib sync flush, so
// the file on disk is always a valid rawlog up to its last complete object: a
// crash leaves a truncated file whose complete objects MRPT reads back.
//
// A long run can cut the stream into files of N maps (segment_maps) and delete the
// files whose maps all fell out of the newest keep_maps, so a robot that maps all
// day keeps its disk (a map every 3 s is ~1.3 GB an hour in one file).
#pragma once

#include <mrpt/obs/CObservation.h>
#include <pndt/app/gz_rawlog_file.h>
#include <pndt/app/writer_thread.h>
#include <pndt/mrpt/PanopticNDTMap.h>

#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

namespace pndt::app
{
struct MapRawlogOptions
{
    /// Written from scratch (truncated if it exists) once the first object is written. With
    /// segment_maps, the files are named after it with the segment's number: maps.rawlog ->
    /// maps-0000.rawlog, ...
    std::string path;
    std::string sensor_label = "PANOPTIC_MAP";
    int compression = 1;                      ///< gzip level 0..9 (1: fastest, as MRPT's default)
    /// Input observations held back until mapping passes their time; beyond this
    /// many the oldest is written anyway (memory stays bounded if frames are not mapped).
    size_t max_held_inputs = 64;
    /// Objects queued for the writer thread before addInput()/addMap() wait (back-pressure).
    size_t max_queued = 32;
    /// Maps per file (0 = one file, `path`). Each file is a complete rawlog; the inputs
    /// interleaved after a file's last map go into the next file, opened with them.
    size_t segment_maps = 0;
    /// With segments: a closed file none of whose maps is among the newest keep_maps
    /// maps is deleted (0 = keep every file). Needs segment_maps.
    size_t keep_maps = 0;
};

class MapRawlogWriter
{
   public:
    /// Checks that the file's folder is writable (io::WriteError naming the file if not);
    /// the file is created (truncated) with the first object written.
    explicit MapRawlogWriter(MapRawlogOptions options);
    /// Writes what is queued and held, swallowing errors (call finish() to see them).
    ~MapRawlogWriter();
    MapRawlogWriter(const MapRawlogWriter&) = delete;
    MapRawlogWriter& operator=(const MapRawlogWriter&) = delete;

    /// An input observation (interleaving): written once mapping has passed its
    /// timestamp (mappedUpTo) or a later map is added, so the file stays in time order.
    void addInput(const mrpt::obs::CObservation::Ptr& obs);
    /// Mapping has integrated every frame up to sensor time `t` (seconds).
    void mappedUpTo(double t);
    /// A handed-over (finalised, no longer modified) map: stamp = `t_end`, its last
    /// frame's time. Written after the held inputs up to that time.
    void addMap(const PanopticNDTMap::Ptr& map, double t_start, double t_end, uint64_t frames, uint32_t sequence);
    /// Writes everything still held or queued, closes the file and rethrows the
    /// writer thread's error (io::WriteError). Idempotent.
    void finish();

    const std::string& path() const { return options_.path; }
    /// Cut into files of segment_maps maps (segmentPath(k)), not one file at path().
    bool segmented() const { return options_.segment_maps > 0; }
    /// The file of segment k (path() itself without segments).
    std::string segmentPath(size_t k) const;
    /// Files opened so far (0 before the first object, then 1 without segments) and, of them,
    /// deleted (keep_maps).
    size_t filesWritten() const;
    size_t filesDeleted() const;
    uint64_t mapsWritten() const;
    uint64_t inputsWritten() const;
    /// Compressed bytes written so far (deleted files included).
    uint64_t bytesWritten() const;
    /// Seconds the writer thread spent serialising, compressing and flushing.
    double secondsWriting() const;

   private:
    using Item = std::pair<mrpt::serialization::CSerializable::Ptr, bool>;  ///< object, is a map
    void release(double t);
    void enqueue(mrpt::serialization::CSerializable::Ptr obj, bool is_map);
    void write(const Item& item);           // writer thread
    void openFile();                        // the next segment (writer thread, or the constructor)
    void closeFile();                       // the current one, its size added to closed_bytes_
    void deleteOldFiles(uint64_t maps_done);  // segments beyond keep_maps (writer thread)

    MapRawlogOptions options_;
    std::unique_ptr<GzRawlogFile> file_;  ///< the segment being written (null between segments)
    // Segments: next to open, first not yet deleted; bytes of the closed files.
    size_t next_file_ = 0, first_kept_file_ = 0;
    uint64_t closed_bytes_ = 0;
    std::deque<mrpt::obs::CObservation::Ptr> held_;  ///< inputs not yet passed by mapping (caller's thread)
    uint64_t maps_done_ = 0;          ///< maps in a file, for the cuts (writer thread; maps_ counts those whose cut and clean-up also succeeded)
    bool finished_ = false;           ///< finish() ran (caller's thread)
    std::exception_ptr close_error_;  ///< the last file's close failed

    mutable std::mutex mutex_;  ///< the file counters above and the counts below, read by other threads
    uint64_t maps_ = 0, inputs_ = 0, bytes_ = 0;
    WriterThread<Item> writer_;  ///< last: its thread starts once the rest is in place
};

/// For the apps' summaries: "" for one file, else where the segments are, e.g.
/// " in maps-0003.rawlog .. maps-0004.rawlog; the 3 older files deleted".
std::string rawlogFilesNote(const MapRawlogWriter& writer);

}  // namespace pndt::app
