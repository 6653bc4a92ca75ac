// Poses that arrive while mapping (issue #19): text lines from TCP connections, UDP datagrams
// or a pose file being appended to, and CObservationRobotPose objects from an MRPT grabber.
// Every pose becomes a CObservationRobotPose in the MRPT robot frame (the same object is
// recorded in the live rawlog and fed to the pose track, so a replay with pndt-map sees the
// very same numbers).
#pragma once

#include <mrpt/obs/CObservationRobotPose.h>
#include <pndt/app/pose_track.h>
#include <pndt/io/poses.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace pndt::live
{
/// Line formats of a pose stream: "tum" (`t x y z qx qy qz qw`, optical camera frame) and
/// RTAB-Map's "rtabmap10" / "rtabmap11" (`t x y z qx qy qz qw [id]`, robot frame, the
/// default export). parsePoseLine returns nullopt for blank and '#' lines and throws
/// InputError naming `where` and the expected layout for anything else that does not parse.
enum class LineFormat
{
    Tum,
    Rtabmap10,
    Rtabmap11
};
LineFormat parseLineFormat(const std::string& name);
std::optional<io::StampedPose> parsePoseLine(const std::string& line, LineFormat f, const std::string& where);

/// Poses received so far, in time order, shared between the sources' threads and the mapper.
class LivePoseBuffer
{
   public:
    /// `clock_offset` (seconds) is added to every pose stamp (localiser clock -> frame clock).
    LivePoseBuffer(std::string label = "LIVE_POSE", double clock_offset = 0) : label_(std::move(label)), offset_(clock_offset) {}

    /// A pose of `frame` (camera: optical frame; robot: MRPT/ROS base frame). Poses not after
    /// the last one are dropped and counted (a reconnecting localiser repeating itself).
    void add(const io::StampedPose& p, app::PoseFrame frame);
    /// A pose from an MRPT grabber, taken as is (robot frame).
    void add(const mrpt::obs::CObservationRobotPose& p);

    /// Waits until a pose at or after `t` arrived (true), or `max_wait_s` passed / stop() (false).
    bool waitFor(double t, double max_wait_s);
    /// Moves out the poses received since the last call, in order.
    std::vector<mrpt::obs::CObservationRobotPose::Ptr> take();
    /// Newest pose stamp (or -inf).
    double latest() const;
    void stop();

    uint64_t received() const { return received_; }
    uint64_t droppedOutOfOrder() const { return out_of_order_; }
    std::atomic<uint64_t> bad_lines{0};
    std::atomic<uint64_t> connections{0};
    std::atomic<int> open_connections{0};

   private:
    void push(mrpt::obs::CObservationRobotPose::Ptr p);
    std::string label_;
    double offset_;
    mutable std::mutex m_;
    std::condition_variable cv_;
    std::deque<mrpt::obs::CObservationRobotPose::Ptr> fresh_;
    double latest_ = -1e300;
    bool stopped_ = false;
    std::atomic<uint64_t> received_{0}, out_of_order_{0};
};

/// A source feeding a LivePoseBuffer from its own thread until destroyed.
class PoseSource
{
   public:
    virtual ~PoseSource() = default;
    virtual std::string describe() const = 0;
};

/// Listens on TCP `port` (0.0.0.0; 0 = any free port, see port()); every connection (one
/// per localiser) sends lines; a closed connection may reconnect at any time.
std::unique_ptr<PoseSource> tcpPoseServer(int port, LineFormat f, app::PoseFrame frame, LivePoseBuffer& buffer,
                                          int* bound_port = nullptr);
/// Receives datagrams of one or more lines on UDP `port`.
std::unique_ptr<PoseSource> udpPoseReceiver(int port, LineFormat f, app::PoseFrame frame, LivePoseBuffer& buffer);
/// Follows a pose file being appended to (like tail -f), from its beginning; the file may
/// appear later.
std::unique_ptr<PoseSource> tailPoseFile(const std::string& path, LineFormat f, app::PoseFrame frame,
                                         LivePoseBuffer& buffer);

/// Runs an MRPT grabber (any mrpt::hwdrivers::CGenericSensor, e.g. one whose observations
/// are CObservationRobotPose) from section `section` of the .ini file `ini` (its `driver` key
/// names the class, as for rawlog-grabber) and takes its CObservationRobotPose observations
/// (robot frame; the buffer's clock offset added; other observations ignored). MRPT 2.5.8's
/// own sensor classes produce none, so the section's `plugin` key may name modules (comma-
/// separated .so files, mrpt::system::loadPluginModules) that register the class. Throws
/// naming the file and section if a plugin does not load, the driver is unknown or does not
/// initialise.
std::unique_ptr<PoseSource> mrptGrabberPoses(const std::string& ini, const std::string& section,
                                             LivePoseBuffer& buffer);

}  // namespace pndt::live
