// OpenNI2 driver of a virtual RGB-D camera (OniDriverAPI): announces one device and streams
// the pndt_sim scene of virtual_scene.h — DEPTH_1_MM, RGB888 and (because MRPT's
// COpenNI2Sensor opens it) an IR stream in RGB888 — at the configured size and rate, stamped
// with device time k / fps (clock_file: the host clock at device time 0). The OpenNI2 runtime loads it from
// <folder of libOpenNI2.so.0 as loaded>/OpenNI2/Drivers/libPndtVirtualCamera.so.0.
#define XN_NEW(type, arg) new type(arg)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>
#include <pndt/oni_virtual/virtual_scene.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace
{
using namespace pndt::oni_virtual;

struct Shared  // what the device's streams read
{
    VirtualCameraConfig config;
    VirtualFrames frames;
    OniDeviceInfo info{};
    std::atomic<bool> unplugged{false};
    std::function<void()> on_unplug;
    std::once_flag rendered, clock_started;
    std::chrono::steady_clock::time_point t0;  ///< device time 0
    /// Rendered at the first stream start (not at open: --list-devices opens devices too).
    const VirtualFrames& loop()
    {
        std::call_once(rendered, [this] { frames = renderLoop(config); });
        return frames;
    }
    /// The device clock, started by the first stream and shared by all: frame k of every stream
    /// is raised at device time k / fps, as on a device whose streams are synchronised.
    /// clock_file gets the host clock at device time 0, read between two readings of the
    /// steady clock less than 0.2 ms apart: a thread preempted between the two clock reads
    /// (33 ms once, on a loaded CI machine) put every host stamp a frame off.
    std::chrono::steady_clock::time_point deviceClock()
    {
        std::call_once(clock_started, [this] {
            double host0 = 0;
            for (int attempt = 0; attempt < 1000; ++attempt)
            {
                const auto before = std::chrono::steady_clock::now();
                host0 = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
                const auto after = std::chrono::steady_clock::now();
                t0 = before + (after - before) / 2;
                if (after - before < std::chrono::microseconds(200)) break;
            }
            if (config.clock_file.empty()) return;
            const std::string tmp = config.clock_file + ".tmp";  // written, then renamed: all or nothing
            if (FILE* f = std::fopen(tmp.c_str(), "w"))
            {
                std::fprintf(f, "%.6f\n", host0);
                std::fclose(f);
                std::rename(tmp.c_str(), config.clock_file.c_str());
            }
        });
        return t0;
    }
};

class VirtualStream : public oni::driver::StreamBase
{
   public:
    VirtualStream(OniSensorType type, std::shared_ptr<Shared> s) : type_(type), s_(std::move(s)) {}
    ~VirtualStream() override { stop(); }

    OniVideoMode mode() const
    {
        OniVideoMode m{};
        m.pixelFormat = type_ == ONI_SENSOR_DEPTH ? ONI_PIXEL_FORMAT_DEPTH_1_MM : ONI_PIXEL_FORMAT_RGB888;
        m.resolutionX = s_->config.width;
        m.resolutionY = s_->config.height;
        m.fps = s_->config.fps;
        return m;
    }
    int bytesPerPixel() const { return type_ == ONI_SENSOR_DEPTH ? 2 : 3; }
    int getRequiredFrameSize() override { return s_->config.width * s_->config.height * bytesPerPixel(); }

    OniStatus start() override
    {
        if (running_) return ONI_STATUS_OK;
        s_->loop();
        running_ = true;
        thread_ = std::thread([this] { run(); });
        return ONI_STATUS_OK;
    }
    void stop() override
    {
        running_ = false;
        if (thread_.joinable()) thread_.join();
    }

    OniBool isPropertySupported(int id) override
    {
        switch (id)
        {
            case ONI_STREAM_PROPERTY_VIDEO_MODE:
            case ONI_STREAM_PROPERTY_MIRRORING:
            case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
            case ONI_STREAM_PROPERTY_VERTICAL_FOV:
            case ONI_STREAM_PROPERTY_MAX_VALUE:
            case ONI_STREAM_PROPERTY_MIN_VALUE: return TRUE;
            default: return FALSE;
        }
    }
    OniStatus getProperty(int id, void* data, int* size) override
    {
        const auto K = s_->config.intrinsics();
        switch (id)
        {
            case ONI_STREAM_PROPERTY_VIDEO_MODE:
                if (*size != sizeof(OniVideoMode)) return ONI_STATUS_ERROR;
                *static_cast<OniVideoMode*>(data) = mode();
                return ONI_STATUS_OK;
            case ONI_STREAM_PROPERTY_MIRRORING:
                if (*size != sizeof(OniBool)) return ONI_STATUS_ERROR;
                *static_cast<OniBool*>(data) = mirror_;
                return ONI_STATUS_OK;
            case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
                if (*size != sizeof(float)) return ONI_STATUS_ERROR;
                *static_cast<float*>(data) = float(2 * std::atan(K.width / (2 * K.fx)));
                return ONI_STATUS_OK;
            case ONI_STREAM_PROPERTY_VERTICAL_FOV:
                if (*size != sizeof(float)) return ONI_STATUS_ERROR;
                *static_cast<float*>(data) = float(2 * std::atan(K.height / (2 * K.fy)));
                return ONI_STATUS_OK;
            case ONI_STREAM_PROPERTY_MAX_VALUE:
            case ONI_STREAM_PROPERTY_MIN_VALUE:
                if (*size != sizeof(int)) return ONI_STATUS_ERROR;
                *static_cast<int*>(data) = id == ONI_STREAM_PROPERTY_MAX_VALUE ? 10000 : 0;
                return ONI_STATUS_OK;
            default: return ONI_STATUS_NOT_SUPPORTED;
        }
    }
    OniStatus setProperty(int id, const void* data, int size) override
    {
        if (id == ONI_STREAM_PROPERTY_MIRRORING && size == sizeof(OniBool))
        {
            mirror_ = *static_cast<const OniBool*>(data);
            return ONI_STATUS_OK;
        }
        if (id == ONI_STREAM_PROPERTY_VIDEO_MODE && size == sizeof(OniVideoMode))
        {
            const auto& m = *static_cast<const OniVideoMode*>(data);
            const auto own = mode();
            return m.resolutionX == own.resolutionX && m.resolutionY == own.resolutionY && m.fps == own.fps &&
                           m.pixelFormat == own.pixelFormat
                       ? ONI_STATUS_OK
                       : ONI_STATUS_NOT_SUPPORTED;
        }
        return ONI_STATUS_NOT_IMPLEMENTED;
    }

   private:
    void run()
    {
        const auto& c = s_->config;
        const auto t0 = s_->deviceClock();
        const auto frame_time = [&](int64_t k) { return t0 + std::chrono::microseconds(k * 1000000 / c.fps); };
        // A stream started later begins at the device's current frame (up to half a frame late).
        int64_t k0 = 0;
        while (frame_time(k0) + std::chrono::microseconds(500000 / c.fps) < std::chrono::steady_clock::now()) ++k0;
        const int W = c.width, H = c.height, bpp = bytesPerPixel();
        for (int64_t k = k0; running_; ++k)
        {
            std::this_thread::sleep_until(frame_time(k));
            if (!running_) break;
            if (c.unplug_after > 0 && k >= c.unplug_after)
            {
                if (!s_->unplugged.exchange(true) && s_->on_unplug) s_->on_unplug();
                break;
            }
            if (c.freeze_after > 0 && k >= c.freeze_after) continue;  // a hung camera: silent, still "connected"
            OniFrame* f = getServices().acquireFrame();
            if (!f) continue;
            const size_t i = size_t(k % c.loop_frames);
            const void* src = type_ == ONI_SENSOR_DEPTH ? static_cast<const void*>(s_->frames.depth_mm[i].data())
                                                        : static_cast<const void*>(s_->frames.rgb[i].data());
            std::memcpy(f->data, src, size_t(W) * H * bpp);
            f->frameIndex = int(k + 1);
            int64_t clock_k = c.clock_reset_after > 0 && k >= c.clock_reset_after ? k - c.clock_reset_after : k;
            if (c.stamp_back_frame > 0 && k == c.stamp_back_frame) clock_k = std::max<int64_t>(0, clock_k - 5);
            if (c.clock_jump_after > 0 && k >= c.clock_jump_after) clock_k += c.clock_jump_frames;
            f->timestamp = uint64_t(clock_k) * 1000000ull / uint64_t(c.fps);
            f->videoMode = mode();
            f->width = W;
            f->height = H;
            f->cropOriginX = f->cropOriginY = 0;
            f->croppingEnabled = FALSE;
            f->stride = W * bpp;
            f->sensorType = type_;
            raiseNewFrame(f);
            getServices().releaseFrame(f);
        }
    }

    OniSensorType type_;
    std::shared_ptr<Shared> s_;
    std::atomic<bool> running_{false};
    OniBool mirror_ = FALSE;
    std::thread thread_;
};

class VirtualDevice : public oni::driver::DeviceBase
{
   public:
    explicit VirtualDevice(std::shared_ptr<Shared> s) : s_(std::move(s))
    {
        static const OniSensorType types[3] = {ONI_SENSOR_DEPTH, ONI_SENSOR_COLOR, ONI_SENSOR_IR};
        for (int i = 0; i < 3; ++i)
        {
            VirtualStream probe(types[i], s_);
            modes_[i] = probe.mode();
            sensors_[i].sensorType = types[i];
            sensors_[i].numSupportedVideoModes = 1;
            sensors_[i].pSupportedVideoModes = &modes_[i];
        }
    }
    OniStatus getSensorInfoList(OniSensorInfo** infos, int* n) override
    {
        *infos = sensors_;
        *n = 3;
        return ONI_STATUS_OK;
    }
    oni::driver::StreamBase* createStream(OniSensorType t) override
    {
        if (t != ONI_SENSOR_DEPTH && t != ONI_SENSOR_COLOR && t != ONI_SENSOR_IR) return nullptr;
        return new VirtualStream(t, s_);
    }
    void destroyStream(oni::driver::StreamBase* p) override { delete p; }
    OniBool isImageRegistrationModeSupported(OniImageRegistrationMode) override { return TRUE; }
    OniBool isPropertySupported(int id) override { return id == ONI_DEVICE_PROPERTY_SERIAL_NUMBER || id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION; }
    OniStatus getProperty(int id, void* data, int* size) override
    {
        if (id == ONI_DEVICE_PROPERTY_SERIAL_NUMBER)
        {
            if (*size < int(s_->config.serial.size() + 1)) return ONI_STATUS_ERROR;
            std::strcpy(static_cast<char*>(data), s_->config.serial.c_str());
            *size = int(s_->config.serial.size() + 1);
            return ONI_STATUS_OK;
        }
        if (id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION && *size == sizeof(OniImageRegistrationMode))
        {
            *static_cast<OniImageRegistrationMode*>(data) = registration_;
            return ONI_STATUS_OK;
        }
        return ONI_STATUS_NOT_SUPPORTED;
    }
    OniStatus setProperty(int id, const void* data, int size) override
    {
        // The scene is rendered from one viewpoint: depth and colour are registered either way.
        if (id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION && size == sizeof(OniImageRegistrationMode))
        {
            registration_ = *static_cast<const OniImageRegistrationMode*>(data);
            return ONI_STATUS_OK;
        }
        return ONI_STATUS_NOT_SUPPORTED;
    }

   private:
    std::shared_ptr<Shared> s_;
    OniVideoMode modes_[3];
    OniSensorInfo sensors_[3];
    OniImageRegistrationMode registration_ = ONI_IMAGE_REGISTRATION_OFF;
};

class VirtualDriver : public oni::driver::DriverBase
{
   public:
    explicit VirtualDriver(OniDriverServices* s) : DriverBase(s) {}

    OniStatus initialize(oni::driver::DeviceConnectedCallback c, oni::driver::DeviceDisconnectedCallback d,
                         oni::driver::DeviceStateChangedCallback sc, void* cookie) override
    {
        DriverBase::initialize(c, d, sc, cookie);
        try
        {
            config_ = VirtualCameraConfig::fromEnvironment();
        }
        catch (const std::exception& e)
        {
            std::fprintf(stderr, "pndt virtual camera: %s\n", e.what());
            return ONI_STATUS_ERROR;
        }
        std::snprintf(info_.uri, sizeof info_.uri, "%s", config_.uri.c_str());
        std::snprintf(info_.vendor, sizeof info_.vendor, "PanopticNDT");
        std::snprintf(info_.name, sizeof info_.name, "Virtual RGB-D camera (pndt_sim)");
        info_.usbVendorId = 0x1d27;  // announced like a PrimeSense-family device
        info_.usbProductId = 0x0601;
        deviceConnected(&info_);
        return ONI_STATUS_OK;
    }
    OniStatus tryDevice(const char* uri) override
    {
        return config_.uri == uri ? ONI_STATUS_OK : ONI_STATUS_ERROR;
    }
    oni::driver::DeviceBase* deviceOpen(const char* uri, const char*) override
    {
        if (config_.uri != uri) return nullptr;
        auto s = std::make_shared<Shared>();
        s->config = config_;
        s->info = info_;
        s->on_unplug = [this] { deviceDisconnected(&info_); };
        return new VirtualDevice(std::move(s));
    }
    void deviceClose(oni::driver::DeviceBase* d) override { delete d; }
    void shutdown() override {}

   private:
    VirtualCameraConfig config_;
    OniDeviceInfo info_{};
};
}  // namespace

ONI_EXPORT_DRIVER(VirtualDriver)
