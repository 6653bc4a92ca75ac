// Observations of a rawlog in file order, either format (observations-only or
// actions/sensory-frames), with a clear account of where a damaged file stops.
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/serialization/CArchive.h>

#include <deque>
#include <memory>
#include <set>
#include <string>

namespace pndt::app
{
class GzFileInput;

/// What happens to rawlog objects (or parts of them) whose layout the reader does not check
/// before MRPT allocates from them: another sensor's observation (a 2D laser scan, an IMU or
/// GPS reading), a scan whose range image lives in a file of its own.
enum class UncheckedObjects
{
    ReadByMrpt,  ///< MRPT reads them as it is; each kind is said once on stderr
    Refused,     ///< reading stops there, naming the class (fuzzing: nothing unchecked)
};

class ObservationStream
{
   public:
    /// Throws std::runtime_error naming the file if it is missing or unreadable.
    explicit ObservationStream(const std::string& path,
                               UncheckedObjects unchecked = UncheckedObjects::ReadByMrpt);
    ~ObservationStream();

    /// The next observation, or nullptr at the end of the file. After nullptr,
    /// truncated() tells whether the file ended cleanly.
    mrpt::obs::CObservation::Ptr next();

    bool truncated() const { return truncated_; }
    /// Why reading stopped early: file, object number, byte position, cause.
    const std::string& stopReason() const { return stop_reason_; }
    size_t objectsRead() const { return objects_; }
    /// Objects MRPT read without this reader's size checks (UncheckedObjects::ReadByMrpt).
    size_t uncheckedObjectsRead() const { return unchecked_objects_; }
    /// Fraction of the file on disk consumed (compressed bytes), for progress bars.
    double progress() const;
    const std::string& path() const { return path_; }

   private:
    class GuardedInput;
    std::unique_ptr<GzFileInput> file_;
    std::string path_;
    std::unique_ptr<GuardedInput> input_;  ///< file_, failing reads that end inside an object
    std::string object_bytes_;  ///< the current object's checked bytes, parsed by MRPT from memory
    std::deque<mrpt::obs::CObservation::Ptr> queued_;  ///< rest of a sensory frame
    size_t objects_ = 0, unchecked_objects_ = 0;
    UncheckedObjects unchecked_;
    std::set<std::string> unchecked_reported_;  ///< kinds of unchecked parts said on stderr
    bool ended_ = false, truncated_ = false;
    std::string stop_reason_;
};

}  // namespace pndt::app
