// Poses from the external localiser, interpolated to frame times.
#pragma once

#include <mrpt/poses/CPose3D.h>
#include <pndt/io/pose_interpolator.h>
#include <pndt/io/poses.h>

#include <mrpt/obs/CObservationRobotPose.h>

#include <optional>
#include <string>

namespace pndt::app
{
/// What a pose describes.
enum class PoseFrame
{
    Robot,   ///< the robot base (MRPT/ROS axes); the camera is robot ⊕ extrinsic
    Camera,  ///< the camera's optical frame (x right, y down, z forward)
};
PoseFrame parsePoseFrame(const std::string& s);  ///< "robot" | "camera"
/// The frame a format's poses are in unless told otherwise: camera for TUM,
/// KITTI, Redwood, nicr; robot for the RTAB-Map exports.
PoseFrame defaultPoseFrame(io::PoseFormat f);

/// A time-sorted pose track with SLERP interpolation and a maximum gap; or, for a pose file
/// without stamps, poses by index (the k-th depth frame takes the k-th pose).
class PoseTrack
{
   public:
    PoseTrack(std::vector<io::StampedPose> poses, PoseFrame frame, double max_gap, std::string source);

    /// An empty track of a rawlog's robot poses (those labelled `label`, or all
    /// when empty; robot frame), filled while the rawlog is replayed
    /// (addRobotPose): one pass over the file.
    static PoseTrack whileReading(const std::string& rawlog, const std::string& label, double max_gap);
    /// Appends `p` if its label is the track's; throws naming the file if it
    /// goes back in time. Returns whether it was taken.
    bool addRobotPose(const mrpt::obs::CObservationRobotPose& p);
    /// A pose file in any format pndt_io reads. Stampless formats (rtabmap0/2/4, kitti,
    /// redwood) give a track by index (byIndex(), cameraAtIndex).
    static PoseTrack fromFile(const std::string& path, io::PoseFormat format, std::optional<PoseFrame> frame,
                              double max_gap);

    /// The optical camera pose at time t, or nullopt if no pose is within the
    /// gap. `extrinsic` = robot -> camera (MRPT sensor axes), used for robot poses.
    std::optional<Pose> cameraAt(double t, const mrpt::poses::CPose3D& extrinsic) const;
    /// A stampless file's track: frames find their pose by their index, not their time.
    bool byIndex() const { return by_index_; }
    /// The optical camera pose of depth frame k (0-based) of a track by index, or nullopt if
    /// the file has none for it (past its end, or a non-finite pose there).
    std::optional<Pose> cameraAtIndex(size_t k, const mrpt::poses::CPose3D& extrinsic) const;
    /// Seconds added to every pose stamp (localiser clock -> camera clock, as pndt-live's
    /// --clock-offset): a pose stamped s is the pose at camera time s + offset.
    void setClockOffset(double seconds) { clock_offset_ = seconds; }
    /// How far back of the newest frame placed a frame may still find its pose: the mappers
    /// let go of older poses (forgetBefore) so that a track fed for hours (pndt-live's
    /// localiser, a long rawlog's robot poses) stays small. A frame further back is skipped.
    static constexpr double kKeptSeconds = 60.0;
    /// Lets go of the poses no frame at camera time >= t needs (PoseInterpolator::forgetBefore).
    void forgetBefore(double t)
    {
        if (!by_index_) interp_.forgetBefore(t - clock_offset_);
    }
    size_t size() const { return by_index_ ? indexed_size_ : interp_.size(); }  ///< poses held
    bool empty() const { return size() == 0; }
    /// Time of the last pose on the camera clock (throws if empty): frames up to it have their
    /// final pose.
    double endTime() const { return interp_.endTime() + clock_offset_; }
    PoseFrame frame() const { return frame_; }
    const std::string& source() const { return source_; }

   private:
    PoseTrack(PoseFrame frame, double max_gap, std::string source, std::string label);

    io::PoseInterpolator interp_;
    std::string label_;  ///< robot poses taken by addRobotPose (empty: all)
    PoseFrame frame_;
    double max_gap_;
    std::string source_;
    double clock_offset_ = 0;
    bool by_index_ = false;
    std::vector<std::optional<Pose>> indexed_;  ///< by_index_: pose k of the file (gaps: non-finite)
    size_t indexed_size_ = 0;
    std::optional<Pose> toCamera(const Pose& p, const mrpt::poses::CPose3D& extrinsic) const;
};

}  // namespace pndt::app
