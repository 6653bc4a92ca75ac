// RGB-D capture through MRPT's mrpt::hwdrivers::COpenNI2Sensor (issue #19), the second backend
// of pndt-live (`--capture mrpt`; OniCapture is OpenNI2's own API). It gives the same design §5
// observation as OniCapture: a CObservation3DRangeScan with the uint16 millimetre depth, the
// registered colour as its intensity image and the intrinsics. What COpenNI2Sensor lacks is
// handled here:
//  - intrinsics: MRPT takes them from the `<section>_LEFT` calibration keys of an MRPT .ini
//    or, without them, from the depth stream's fields of view (the same formula as
//    OniCapture); `K` (pndt-live --intrinsics) overrides both;
//  - stamps: MRPT stamps a frame with the host clock when it has read it (the device stamp is
//    lost), so CapturedFrame::device_t is that host time. Poses must then be on the host clock
//    (a localiser on the same machine stamping with the system clock; --clock-offset for a
//    constant lag);
//  - a camera that goes away: getNextObservation() blocks forever (OpenNI2 readFrame without
//    a timeout), so it runs on its own thread and grab() waits with a timeout; OpenNI2's
//    disconnect report (OniDisconnectWatch) is seen at once. A grab thread still blocked in
//    MRPT when the capture is destroyed is left behind with the sensor it uses (abandoned()).
#pragma once

#include <pndt/live/live_pipeline.h>

#include <memory>
#include <string>

namespace pndt::live
{
struct MrptCaptureOptions
{
    OniCaptureOptions camera;  ///< device (resolved through OpenNI2's enumeration), size, fps, K, label
    /// Optional MRPT .ini with a COpenNI2Sensor section (calibration `<section>_LEFT`/_RIGHT/
    /// _LEFT2RIGHT_POSE, relativePoseIntensityWRTDepth, ...); width, height, fps, device and
    /// the grab keys are pndt-live's.
    std::string ini;
    std::string section = "OPENNI2";
    /// Frames waiting for grab() before the oldest is replaced (OpenNI2 itself keeps only a
    /// stream's newest frame).
    size_t queue = 4;
};

class MrptCapture : public FrameGrabber
{
   public:
    /// Loads the configuration into a COpenNI2Sensor, initialises it (opens the device and its
    /// streams) and starts the grab thread; throws naming the device and the problem.
    explicit MrptCapture(const MrptCaptureOptions& o);
    ~MrptCapture() override;
    /// The next frame, or nullopt after `timeout_s` without one, once the device was reported
    /// disconnected (frames already read are still returned), or after MRPT threw.
    std::optional<CapturedFrame> grab(double timeout_s) override;
    bool disconnected() const override;
    std::string lostReason() const override;
    /// Ends the grab thread after its current read (frames after it are not counted as replaced).
    void stopCapture() override;
    std::string describe() const;
    const CameraIntrinsics& intrinsics() const;
    /// Frames replaced in the hand-over queue because grab() was not called in time.
    uint64_t replaced() const;
    /// True once the destructor had to leave the grab thread blocked inside MRPT.
    static bool abandoned();

   private:
    struct Shared;
    std::shared_ptr<Shared> s_;
};

}  // namespace pndt::live
