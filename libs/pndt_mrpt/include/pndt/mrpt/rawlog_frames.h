// Rawlogs in the design §5 shape: per frame a CObservation3DRangeScan, the two
// float32 panoptic CObservationImages (same timestamp) and, when known, a
// CObservationRobotPose — all readable by stock MRPT tools without the plugin.
#pragma once

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <pndt/frame.h>

#include <array>
#include <memory>
#include <optional>
#include <string>

namespace pndt
{
/// Pose convention of written rawlogs: the CObservationRobotPose holds the
/// camera's pose in MRPT sensor axes (x forward, y left, z up) and the range
/// scan's sensorPose is identity, unless a robot->camera extrinsic is given.
class RawlogFrameWriter
{
   public:
    /// Opens `path` for writing through a temporary file; nothing appears at
    /// `path` until commit().
    explicit RawlogFrameWriter(std::string path, std::string rgbd_label = "RGBD", int gz_level = 1);
    ~RawlogFrameWriter();  // without commit(): the temporary file is removed

    /// Robot -> camera (MRPT sensor axes) extrinsic written into every scan.
    void setSensorPose(const mrpt::poses::CPose3D& p) { sensor_pose_ = p; }

    /// Writes one frame at time `t` (seconds). Labels are written when the frame
    /// has them; `T_world_cam` (optical camera in the world) as a robot pose
    /// observation labelled `pose_label`; `rgb` (row-major RGB) as the scan's
    /// intensity image.
    void write(const PanopticFrame& frame, double t, const std::optional<Pose>& T_world_cam,
               const Image<std::array<uint8_t, 3>>* rgb = nullptr, const std::string& pose_label = "GT_POSE");
    /// Any other observation, as is.
    void writeObservation(const mrpt::obs::CObservation& obs);

    void commit();
    size_t framesWritten() const { return frames_; }
    /// Positive depths of the frames written that a rawlog could not store (rangeScanFrom).
    size_t unstoredDepthPixels() const { return unstored_depth_; }
    const std::string& label() const { return label_; }

   private:
    std::string path_, tmp_, label_;
    mrpt::poses::CPose3D sensor_pose_;
    std::unique_ptr<mrpt::io::CFileGZOutputStream> out_;
    size_t frames_ = 0;
    size_t unstored_depth_ = 0;
    bool committed_ = false;
};

}  // namespace pndt
