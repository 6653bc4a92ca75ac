// Several rawlogs read as one, in the order given: a recording cut into files
// (pndt-live --record-minutes: rec-0000.rawlog, rec-0001.rawlog, ...) or any rawlog
// cut by time with rawlog-edit. Each file is read by ObservationStream; a damaged
// file ends the sequence there (truncated(), its reason naming that file). A file's
// robot poses no later than the newest pose of the files before it are skipped: a
// recording cut into files starts each file with the poses its first frames need,
// which the file before already held.
#pragma once

#include <pndt/app/observation_stream.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pndt::app
{
class RawlogSequence
{
   public:
    /// Throws std::runtime_error naming the first file that is missing or unreadable
    /// (all are checked here, before anything is read). Files are opened one at a time.
    explicit RawlogSequence(std::vector<std::string> paths);
    ~RawlogSequence();

    /// The next observation, or nullptr after the last file. Throws std::runtime_error
    /// when a file's first range scan is not later than the previous file's last one
    /// (files given out of time order, or one file twice), naming both files.
    mrpt::obs::CObservation::Ptr next();

    bool truncated() const;
    const std::string& stopReason() const;
    /// Fraction of all files' compressed bytes consumed.
    double progress() const;
    /// The file being read (the last one once all are read).
    const std::string& path() const { return paths_[current_]; }
    const std::vector<std::string>& paths() const { return paths_; }

   private:
    std::vector<std::string> paths_;
    std::vector<uint64_t> sizes_;  ///< bytes on disk, for progress()
    uint64_t total_bytes_ = 0, bytes_before_ = 0;  ///< all files; the files already read
    size_t current_ = 0;
    std::unique_ptr<ObservationStream> in_;
    // Time order across files, by range scan stamps (poses may run ahead of the scans).
    double last_scan_t_ = -1e300;
    std::string last_scan_file_;
    bool scan_seen_in_file_ = false;
    double last_pose_t_ = -1e300, pose_t_before_file_ = -1e300;  ///< newest robot pose: so far, before this file
};

}  // namespace pndt::app
