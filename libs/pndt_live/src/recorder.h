// pndt-live's recording (--record): what was seen, as a rawlog pndt-map replays.
// Written from its own thread, in order, each observation flushed to the file as it
// goes: a crash or a full disk leaves a recording that reads back (and replays) up
// to its last complete observation. A write error stops the run at once: push()
// rethrows it on the mapping thread.
//
// Optionally cut into files of a few minutes of sensor time (rec.rawlog ->
// rec-0000.rawlog, rec-0001.rawlog, ..., each a whole rawlog, cut only between
// frames), keeping only the newest few: a black box of the last minutes, so a
// robot that records all day keeps its disk (~16 GB an hour at 640x480 with colour).
// Each new file starts with the poses its first frames need that an earlier file
// already holds (the newest at or before its first frame, and any later ones: a
// localiser may send ahead), so every file replays on its own; pndt-map reading the
// files in a row skips those repeats (RawlogSequence).
#pragma once

#include <mrpt/obs/CObservation.h>
#include <pndt/app/gz_rawlog_file.h>
#include <pndt/app/writer_thread.h>

#include <atomic>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <string>
#include <utility>

namespace pndt::live
{
struct RecorderOptions
{
    std::string path;
    /// Seconds of sensor time per file (0 = one file, `path`). A file ends before the
    /// first frame at least this long after the file's first frame.
    double part_seconds = 0;
    /// With parts: only the newest keep_files files are kept, older ones deleted (0 = all).
    size_t keep_files = 0;
};

class Recorder
{
   public:
    /// Creates the (first) file; throws io::WriteError naming it.
    explicit Recorder(RecorderOptions options);
    ~Recorder();
    Recorder(const Recorder&) = delete;
    Recorder& operator=(const Recorder&) = delete;

    /// What follows belongs to the frame at sensor time `t` (its poses, scan, labels): a
    /// file may end here. Rethrows a write error.
    void startFrame(double t);
    /// Queues an observation. Waits while the queue is full (a disk slower than the camera
    /// holds the mapper back, whose own queue then drops frames, counted). Rethrows a
    /// write error.
    void push(mrpt::obs::CObservation::Ptr o);
    /// Writes what is queued and the gzip trailer; rethrows the first write error. Called
    /// from the thread that pushes (not beside a push).
    void close();

    /// The file of part k (`path` itself without parts).
    std::string filePath(size_t k) const;
    bool cut() const { return options_.part_seconds > 0; }
    /// Range scans written whole (after close(), or while running: a lower bound).
    uint64_t framesWritten() const { return frames_; }
    /// Files opened so far and, of them, deleted (keep_files).
    size_t filesOpened() const { return files_opened_; }
    size_t filesDeleted() const { return files_deleted_; }
    /// Compressed bytes on disk in the files kept (the current one up to its last flush).
    uint64_t bytesKept() const { return bytes_kept_; }

   private:
    static constexpr size_t kMaxQueued = 256;  // ~50 frames: a scan, two label images, poses, a frame start
    /// An observation, or (null) the start of the frame at sensor time `second`.
    using Item = std::pair<mrpt::obs::CObservation::Ptr, double>;
    void enqueue(mrpt::obs::CObservation::Ptr o, double frame_t);
    void write(const mrpt::obs::CObservation::Ptr& o, double frame_t);  // writer thread
    void nextFile();                                                   // writer thread

    RecorderOptions options_;
    std::unique_ptr<app::GzRawlogFile> file_;
    double file_start_t_ = -1;       ///< sensor time of the current file's first frame (-1: none yet)
    uint64_t closed_kept_bytes_ = 0;  ///< bytes of the closed files not deleted
    std::deque<uint64_t> closed_sizes_;  ///< sizes of the closed files not deleted, oldest first
    /// Poses written that a file started now would need: the newest at or before the
    /// current frame, and those after it.
    std::deque<mrpt::obs::CObservation::Ptr> recent_poses_;
    bool closed_ = false;             ///< close() ran (the caller's thread)
    std::exception_ptr close_error_;  ///< the last file's close failed
    std::atomic<uint64_t> frames_{0}, bytes_kept_{0};
    std::atomic<size_t> files_opened_{0}, files_deleted_{0};
    app::WriterThread<Item> writer_;  ///< last: its thread starts once the rest is in place
};

}  // namespace pndt::live
