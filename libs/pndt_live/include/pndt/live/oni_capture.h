// RGB-D capture from an OpenNI2 device (issue #19). Frames become the design §5 rawlog
// observation: a CObservation3DRangeScan with the uint16 millimetre depth (range_is_depth),
// the colour as its intensity image and the intrinsics from the device's fields of view (or
// given). OpenNI2's own API is used here because MRPT 2.5.8's COpenNI2Sensor stamps frames
// with the host clock at grab (the device stamp is lost, so a localiser's poses cannot be
// matched to frames by device time), blocks forever in getNextObservation() when the device
// goes away, and opens an IR stream real devices cannot run together with colour. The
// COpenNI2Sensor backend, with those gaps handled, is MrptCapture (mrpt_capture.h).
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <pndt/types.h>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pndt::live
{
struct OniDeviceEntry
{
    std::string uri, vendor, name, serial;
    int usb_vendor = 0, usb_product = 0;
};
/// Devices OpenNI2 enumerates (initialises OpenNI2; throws with its error text).
std::vector<OniDeviceEntry> listOniDevices();
/// The URI of the device `device` names ("" = the first, a number = index, a serial number or
/// a URI), through OpenNI2's enumeration; `index` (if given) gets its position in the list, or
/// -1 for a URI the enumeration does not list. Throws naming the device.
std::string resolveOniDevice(const std::string& device, int* index = nullptr);

/// Notices OpenNI2's report that the device with `uri` went away (whoever opened it: also a
/// device MRPT's COpenNI2Sensor opened in this process).
class OniDisconnectWatch
{
   public:
    explicit OniDisconnectWatch(const std::string& uri);
    ~OniDisconnectWatch();
    bool gone() const;

   private:
    struct Listener;
    std::unique_ptr<Listener> l_;
};

struct OniCaptureOptions
{
    std::string device;   ///< "" = first; a number = index; a serial; or a URI
    int width = 640, height = 480, fps = 30;
    bool registration = true;     ///< depth registered to colour by the device
    bool color = true;
    std::optional<CameraIntrinsics> K;  ///< default: from the depth stream's fields of view
    std::string sensor_label = "RGBD";
};

/// One grabbed frame: the scan (range + intensity), its device stamp (seconds).
struct CapturedFrame
{
    mrpt::obs::CObservation3DRangeScan::Ptr scan;
    double device_t = 0;
    uint64_t index = 0;
};

class OniCapture
{
   public:
    /// Opens the device and starts its streams; throws naming the device and the problem.
    explicit OniCapture(const OniCaptureOptions& o);
    ~OniCapture();
    /// The next frame (depth, with the colour frame nearest in device time), or nullopt after
    /// `timeout_s` without a frame or when the device was disconnected (see disconnected()).
    std::optional<CapturedFrame> grab(double timeout_s);
    bool disconnected() const;
    std::string describe() const;
    const CameraIntrinsics& intrinsics() const;

   private:
    struct Impl;
    std::unique_ptr<Impl> d_;
};

}  // namespace pndt::live
