#include <fmt/format.h>
#include <pndt/live/oni_capture.h>

#include <OpenNI.h>

#include <cmath>
#include <cstring>
#include <mutex>

namespace pndt::live
{
namespace
{
void initOpenNI()
{
    static std::once_flag once;
    static std::string error;
    std::call_once(once, [] {
        if (openni::OpenNI::initialize() != openni::STATUS_OK)
            error = fmt::format("OpenNI2 did not initialise: {}", openni::OpenNI::getExtendedError());
    });
    if (!error.empty()) throw std::runtime_error(error);
}

std::string serialOf(openni::Device& d)
{
    char s[128] = {};
    int size = sizeof s;
    if (d.getProperty(ONI_DEVICE_PROPERTY_SERIAL_NUMBER, s, &size) != openni::STATUS_OK) return {};
    return s;
}

}  // namespace

struct OniDisconnectWatch::Listener : public openni::OpenNI::DeviceDisconnectedListener
{
    std::string uri;
    std::atomic<bool> gone{false};
    void onDeviceDisconnected(const openni::DeviceInfo* info) override
    {
        if (uri == info->getUri()) gone = true;
    }
};

OniDisconnectWatch::OniDisconnectWatch(const std::string& uri) : l_(std::make_unique<Listener>())
{
    initOpenNI();
    l_->uri = uri;
    openni::OpenNI::addDeviceDisconnectedListener(l_.get());
}
OniDisconnectWatch::~OniDisconnectWatch() { openni::OpenNI::removeDeviceDisconnectedListener(l_.get()); }
bool OniDisconnectWatch::gone() const { return l_->gone; }

std::vector<OniDeviceEntry> listOniDevices()
{
    initOpenNI();
    openni::Array<openni::DeviceInfo> list;
    openni::OpenNI::enumerateDevices(&list);
    std::vector<OniDeviceEntry> out;
    for (int i = 0; i < list.getSize(); ++i)
    {
        OniDeviceEntry e{list[i].getUri(), list[i].getVendor(), list[i].getName(), "", list[i].getUsbVendorId(),
                         list[i].getUsbProductId()};
        openni::Device d;
        if (d.open(list[i].getUri()) == openni::STATUS_OK)
        {
            e.serial = serialOf(d);
            d.close();
        }
        out.push_back(e);
    }
    return out;
}

std::string resolveOniDevice(const std::string& device, int* index)
{
    initOpenNI();
    openni::Array<openni::DeviceInfo> list;
    openni::OpenNI::enumerateDevices(&list);
    std::string uri;
    int at = -1;
    if (device.empty())
    {
        if (list.getSize() == 0)
            throw std::runtime_error("no OpenNI2 device found (is the camera plugged in? pndt-live --list-devices)");
        at = 0;
    }
    else if (device.find_first_not_of("0123456789") == std::string::npos)
    {
        at = std::stoi(device);
        if (at >= list.getSize())
            throw std::runtime_error(fmt::format("OpenNI2 device {}: only {} device(s) found (pndt-live --list-devices)",
                                                 at, list.getSize()));
    }
    else
    {
        for (int i = 0; i < list.getSize() && at < 0; ++i)
        {
            if (device == list[i].getUri()) at = i;
            openni::Device d;
            if (at < 0 && d.open(list[i].getUri()) == openni::STATUS_OK)
            {
                if (serialOf(d) == device) at = i;
                d.close();
            }
        }
    }
    if (index) *index = at;
    return at >= 0 ? list[at].getUri() : device;  // else a URI the enumeration did not list (e.g. a file)
}

struct OniCapture::Impl
{
    OniCaptureOptions o;
    openni::Device device;
    openni::VideoStream depth, color;
    std::unique_ptr<OniDisconnectWatch> watch;
    CameraIntrinsics K;
    std::string uri, name;
    uint64_t index = 0;
    openni::VideoFrameRef last_color;
    bool have_color = false;

    static bool setMode(openni::VideoStream& s, int w, int h, int fps, openni::PixelFormat pf)
    {
        const auto& modes = s.getSensorInfo().getSupportedVideoModes();
        for (int i = 0; i < modes.getSize(); ++i)
            if (modes[i].getResolutionX() == w && modes[i].getResolutionY() == h && modes[i].getFps() == fps &&
                modes[i].getPixelFormat() == pf)
                return s.setVideoMode(modes[i]) == openni::STATUS_OK;
        return false;
    }
    static std::string modesOf(openni::VideoStream& s)
    {
        std::string m;
        const auto& modes = s.getSensorInfo().getSupportedVideoModes();
        for (int i = 0; i < modes.getSize(); ++i)
            m += fmt::format("{}{}x{}@{}", m.empty() ? "" : ", ", modes[i].getResolutionX(), modes[i].getResolutionY(),
                             modes[i].getFps());
        return m;
    }
};

OniCapture::OniCapture(const OniCaptureOptions& o) : d_(std::make_unique<Impl>())
{
    initOpenNI();
    d_->o = o;
    const std::string uri = resolveOniDevice(o.device);
    if (d_->device.open(uri.c_str()) != openni::STATUS_OK)
        throw std::runtime_error(fmt::format("OpenNI2 device '{}': cannot open: {}", o.device.empty() ? uri : o.device,
                                             openni::OpenNI::getExtendedError()));
    d_->uri = uri;
    d_->name = d_->device.getDeviceInfo().getName();
    d_->watch = std::make_unique<OniDisconnectWatch>(uri);
    if (d_->depth.create(d_->device, openni::SENSOR_DEPTH) != openni::STATUS_OK)
        throw std::runtime_error(fmt::format("OpenNI2 device '{}': no depth stream: {}", uri,
                                             openni::OpenNI::getExtendedError()));
    if (!Impl::setMode(d_->depth, o.width, o.height, o.fps, openni::PIXEL_FORMAT_DEPTH_1_MM))
        throw std::runtime_error(fmt::format("OpenNI2 device '{}': no depth mode {}x{}@{} in millimetres (has {})", uri,
                                             o.width, o.height, o.fps, Impl::modesOf(d_->depth)));
    d_->depth.setMirroringEnabled(false);
    if (o.color)
    {
        if (d_->color.create(d_->device, openni::SENSOR_COLOR) != openni::STATUS_OK ||
            !Impl::setMode(d_->color, o.width, o.height, o.fps, openni::PIXEL_FORMAT_RGB888))
            throw std::runtime_error(fmt::format("OpenNI2 device '{}': no colour mode {}x{}@{} RGB888 (use --no-color)",
                                                 uri, o.width, o.height, o.fps));
        d_->color.setMirroringEnabled(false);
        if (o.registration)
        {
            if (!d_->device.isImageRegistrationModeSupported(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR) ||
                d_->device.setImageRegistrationMode(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR) != openni::STATUS_OK)
                throw std::runtime_error(fmt::format(
                    "OpenNI2 device '{}': depth-to-colour registration not supported (use --no-registration)", uri));
        }
        d_->device.setDepthColorSyncEnabled(true);
    }
    if (o.K)
        d_->K = *o.K;
    else
    {
        const double hfov = d_->depth.getHorizontalFieldOfView(), vfov = d_->depth.getVerticalFieldOfView();
        if (!(hfov > 0 && vfov > 0))
            throw std::runtime_error(fmt::format("OpenNI2 device '{}': no field of view to derive intrinsics from; "
                                                 "give --intrinsics 'fx fy cx cy'",
                                                 uri));
        d_->K = CameraIntrinsics{o.width, o.height, o.width / (2 * std::tan(hfov / 2)),
                                 o.height / (2 * std::tan(vfov / 2)), (o.width - 1) / 2.0, (o.height - 1) / 2.0};
    }
    if (d_->depth.start() != openni::STATUS_OK || (o.color && d_->color.start() != openni::STATUS_OK))
        throw std::runtime_error(fmt::format("OpenNI2 device '{}': streams did not start: {}", uri,
                                             openni::OpenNI::getExtendedError()));
}

OniCapture::~OniCapture()
{
    d_->watch.reset();
    d_->depth.stop();
    d_->color.stop();
    d_->depth.destroy();
    d_->color.destroy();
    d_->device.close();
}

bool OniCapture::disconnected() const { return d_->watch->gone(); }
const CameraIntrinsics& OniCapture::intrinsics() const { return d_->K; }
std::string OniCapture::describe() const
{
    return fmt::format("{} ({}), {}x{} @ {} Hz, fx {:.1f} fy {:.1f}", d_->name, d_->uri, d_->o.width, d_->o.height,
                       d_->o.fps, d_->K.fx, d_->K.fy);
}

std::optional<CapturedFrame> OniCapture::grab(double timeout_s)
{
    auto& d = *d_;
    openni::VideoFrameRef depth;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (!depth.isValid())
    {
        // After a disconnect, frames already delivered are still read (a short grace period).
        const bool gone = d.watch->gone();
        const int left_ms = gone ? 50
                                 : int(std::chrono::duration<double, std::milli>(deadline - std::chrono::steady_clock::now())
                                           .count());
        if (left_ms <= 0) return std::nullopt;
        openni::VideoStream* streams[2] = {&d.depth, &d.color};
        int ready = -1;
        if (openni::OpenNI::waitForAnyStream(streams, d.o.color ? 2 : 1, &ready, std::min(left_ms, 100)) !=
            openni::STATUS_OK)
        {
            if (gone) return std::nullopt;
            continue;
        }
        if (ready == 0)
            d.depth.readFrame(&depth);
        else if (ready == 1 && d.color.readFrame(&d.last_color) == openni::STATUS_OK)
            d.have_color = true;
    }
    // Colour of the same device time (the driver streams them in step; a colour frame may
    // still be on its way).
    if (d.o.color)
    {
        const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);
        while ((!d.have_color || d.last_color.getTimestamp() < depth.getTimestamp()) &&
               std::chrono::steady_clock::now() < until && !d.watch->gone())
        {
            openni::VideoStream* s = &d.color;
            int ready = -1;
            if (openni::OpenNI::waitForAnyStream(&s, 1, &ready, 20) == openni::STATUS_OK &&
                d.color.readFrame(&d.last_color) == openni::STATUS_OK)
                d.have_color = true;
        }
    }
    CapturedFrame out;
    out.index = d.index++;
    out.device_t = double(depth.getTimestamp()) * 1e-6;
    auto scan = std::make_shared<mrpt::obs::CObservation3DRangeScan>();
    const int W = depth.getWidth(), H = depth.getHeight();
    scan->sensorLabel = d.o.sensor_label;
    scan->hasRangeImage = true;
    scan->range_is_depth = true;
    scan->rangeUnits = 0.001f;
    scan->rangeImage.resize(H, W);
    const auto* px = static_cast<const uint16_t*>(depth.getData());
    const int stride = depth.getStrideInBytes() / 2;
    for (int r = 0; r < H; ++r) std::memcpy(&scan->rangeImage(r, 0), px + size_t(r) * stride, size_t(W) * 2);
    auto& cp = scan->cameraParams;
    cp.ncols = uint32_t(W);
    cp.nrows = uint32_t(H);
    cp.fx(d.K.fx);
    cp.fy(d.K.fy);
    cp.cx(d.K.cx);
    cp.cy(d.K.cy);
    scan->cameraParamsIntensity = cp;
    // Registered colour sits in the depth camera's frame.
    scan->relativePoseIntensityWRTDepth = mrpt::poses::CPose3D(0, 0, 0, -M_PI / 2, 0, -M_PI / 2);
    if (d.o.color && d.have_color && d.last_color.getWidth() == W && d.last_color.getHeight() == H)
    {
        scan->hasIntensityImage = true;
        scan->intensityImageChannel = mrpt::obs::CObservation3DRangeScan::CH_VISIBLE;
        scan->intensityImage.resize(W, H, mrpt::img::CH_RGB);
        const auto* c = static_cast<const uint8_t*>(d.last_color.getData());
        const int cstride = d.last_color.getStrideInBytes();
        for (int r = 0; r < H; ++r)
        {
            uint8_t* row = scan->intensityImage.ptrLine<uint8_t>(r);  // BGR, as OpenCV
            const uint8_t* src = c + size_t(r) * cstride;
            for (int x = 0; x < W; ++x)
            {
                row[3 * x + 0] = src[3 * x + 2];
                row[3 * x + 1] = src[3 * x + 1];
                row[3 * x + 2] = src[3 * x + 0];
            }
        }
    }
    out.scan = std::move(scan);
    return out;
}

}  // namespace pndt::live
