// The virtual RGB-D camera behind the OpenNI2 driver libPndtVirtualCamera.so.0: a pndt_sim
// scene seen along a deterministic orbit, rendered once per loop position, streamed at `fps`
// with device stamps t_k = k / fps. Its true camera poses can be written as a TUM file, so a
// test (or a demo) can stream them to pndt-live with pndt-pose-send.
//
// Configuration: a `key = value` file named by $PNDT_VIRTUAL_CAMERA (missing variable: the
// defaults below). Unknown keys and bad values are errors naming the file and the key.
#pragma once

#include <pndt/types.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pndt::oni_virtual
{
struct VirtualCameraConfig
{
    int width = 640, height = 480, fps = 30;
    int loop_frames = 90;      ///< rendered poses along one orbit; frame k shows pose k % loop_frames
    uint64_t seed = 1;         ///< start angle of the orbit (deterministic)
    double radius = 2.3;       ///< orbit around the room centre, metres
    double eye_height = 1.5;
    int unplug_after = 0;      ///< frames after which the device reports itself unplugged (0 = never)
    int freeze_after = 0;      ///< frames after which the streams go silent, nothing reported (0 = never)
    /// Frame from which the device clock starts again at 0, as after a firmware reset: frame
    /// k >= clock_reset_after is stamped (k - clock_reset_after) / fps (0 = never).
    int clock_reset_after = 0;
    /// Frame that carries the stamp of the frame five before it, as a frame delivered out of
    /// order; the frames after it are stamped as usual (0 = none).
    int stamp_back_frame = 0;
    /// Frame from which the device clock runs clock_jump_frames frames ahead, as a clock that
    /// jumped forward: frame k >= clock_jump_after is stamped (k + clock_jump_frames) / fps (0 = never).
    int clock_jump_after = 0;
    int clock_jump_frames = 30;
    std::string serial = "PNDT0001";
    std::string uri = "pndt://virtual/0";
    double pose_seconds = 120; ///< length of the TUM pose file writeTrajectoryTum writes
    /// If set: when the depth stream starts, the host clock (Unix seconds) at its device time 0
    /// is written there, so poses can be put on the host clock (pndt-pose-send --stamp-offset)
    /// for capture backends that stamp frames with the host clock (pndt-live --capture mrpt).
    std::string clock_file;

    /// The file named by $PNDT_VIRTUAL_CAMERA, else the defaults.
    static VirtualCameraConfig fromEnvironment();
    static VirtualCameraConfig fromFile(const std::string& path);
    CameraIntrinsics intrinsics() const;
};

/// Optical camera pose (x right, y down, z forward; z-up world) of device frame k.
Pose cameraPoseAt(const VirtualCameraConfig& c, int64_t k);

/// Writes the camera's true poses at every frame stamp for c.pose_seconds as TUM lines
/// `t tx ty tz qx qy qz qw` (atomically; throws naming the file).
void writeTrajectoryTum(const VirtualCameraConfig& c, const std::string& path);

/// The pre-rendered loop: depth in millimetres (0 = no hit) and RGB888, per loop position.
struct VirtualFrames
{
    std::vector<std::vector<uint16_t>> depth_mm;
    std::vector<std::vector<uint8_t>> rgb;
};
VirtualFrames renderLoop(const VirtualCameraConfig& c);

}  // namespace pndt::oni_virtual
