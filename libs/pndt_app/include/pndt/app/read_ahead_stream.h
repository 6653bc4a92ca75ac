// A rawlog's observations decoded on a background thread, a bounded number
// ahead of the consumer: decompressing and deserialising (most of a replay's
// time on real rawlogs) overlap with mapping on another core.
#pragma once

#include <pndt/app/rawlog_sequence.h>

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

namespace pndt::app
{
class ReadAheadStream
{
   public:
    /// Opens `path` (throws like ObservationStream) and starts reading ahead,
    /// at most `depth` observations.
    explicit ReadAheadStream(const std::string& path, size_t depth = 16);
    /// Several rawlogs read one after the other (throws like RawlogSequence).
    explicit ReadAheadStream(std::vector<std::string> paths, size_t depth = 16);
    /// Stops the reader (after the observation it is decoding) and joins it.
    ~ReadAheadStream();
    ReadAheadStream(const ReadAheadStream&) = delete;
    ReadAheadStream& operator=(const ReadAheadStream&) = delete;

    /// The next observation in file order, or nullptr at the end; rethrows an
    /// error the reader met. After nullptr, truncated() and stopReason() tell
    /// why reading ended, as for ObservationStream.
    mrpt::obs::CObservation::Ptr next();
    bool truncated() const;
    const std::string& stopReason() const;
    /// Fraction of the file(s) up to the end of the observation next() returned
    /// last (not of what the reader has read ahead).
    double progress() const;
    const std::vector<std::string>& paths() const { return in_.paths(); }

   private:
    void readLoop();

    RawlogSequence in_;  ///< the reader thread's alone once it runs
    const size_t depth_;
    mutable std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<std::pair<mrpt::obs::CObservation::Ptr, double>> queue_;  ///< with progress()
    bool ended_ = false, stop_ = false;
    std::exception_ptr error_;
    double progress_ = 0;
    std::thread reader_;
};

}  // namespace pndt::app
