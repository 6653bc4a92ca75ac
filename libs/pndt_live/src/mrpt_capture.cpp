#include <fmt/format.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/hwdrivers/COpenNI2Sensor.h>
#include <mrpt/system/datetime.h>
#include <pndt/app/error_text.h>
#include <pndt/live/mrpt_capture.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <thread>

namespace pndt::live
{
namespace
{
std::atomic<bool> g_abandoned{false};


/// MRPT's loadConfig/initialize print progress (and a calibration warning with a backtrace)
/// on std::cout: kept out of pndt-live's output, shown only when they fail.
class CoutCapture
{
   public:
    CoutCapture() : old_(std::cout.rdbuf(buf_.rdbuf())) {}
    ~CoutCapture() { std::cout.rdbuf(old_); }
    std::string text() const { return buf_.str(); }

   private:
    std::ostringstream buf_;
    std::streambuf* old_;
};
}  // namespace

/// Shared with the grab thread, which may outlive the MrptCapture (see abandoned()).
struct MrptCapture::Shared
{
    MrptCaptureOptions o;
    std::unique_ptr<mrpt::hwdrivers::COpenNI2Sensor> sensor;
    std::unique_ptr<OniDisconnectWatch> watch;
    CameraIntrinsics K;
    std::string uri, k_source;
    int index = 0;

    std::mutex m;
    std::condition_variable cv;
    std::deque<CapturedFrame> q;
    std::atomic<bool> stop{false};
    bool done = false;  ///< the grab thread has returned
    std::string error;  ///< why it returned (empty: stopped)
    uint64_t next = 0, replaced = 0;
    std::thread thread;

    void run()
    {
        while (!stop)
        {
            auto obs = std::make_shared<mrpt::obs::CObservation3DRangeScan>();
            bool there = false, hw = false;
            try
            {
                sensor->getNextObservation(*obs, there, hw);  // blocks until the streams deliver
            }
            catch (const std::exception& e)
            {
                std::lock_guard<std::mutex> lk(m);
                error = "MRPT's COpenNI2Sensor: " + app::plainErrorText(e.what());
                break;
            }
            if (hw)
            {
                std::lock_guard<std::mutex> lk(m);
                error = "MRPT's COpenNI2Sensor reported a hardware error";
                break;
            }
            if (!there || !obs->hasRangeImage) continue;
            // The design §5 observation, as OniCapture makes it.
            obs->sensorLabel = o.camera.sensor_label;
            obs->hasPoints3D = false;
            obs->points3D_x.clear(), obs->points3D_y.clear(), obs->points3D_z.clear();
            auto& cp = obs->cameraParams;
            cp.ncols = uint32_t(K.width);
            cp.nrows = uint32_t(K.height);
            cp.fx(K.fx);
            cp.fy(K.fy);
            cp.cx(K.cx);
            cp.cy(K.cy);
            cp.dist.fill(0);
            obs->cameraParamsIntensity = cp;  // colour registered to depth by the device
            if (!o.camera.color)
            {
                obs->hasIntensityImage = false;
                obs->intensityImage = mrpt::img::CImage();
            }
            if (stop) break;
            CapturedFrame f;
            f.device_t = mrpt::Clock::toDouble(obs->timestamp);  // host clock when MRPT read it
            f.scan = std::move(obs);
            {
                std::lock_guard<std::mutex> lk(m);
                f.index = next++;
                q.push_back(std::move(f));
                if (q.size() > std::max<size_t>(1, o.queue))
                {
                    q.pop_front();
                    ++replaced;
                }
            }
            cv.notify_all();
        }
        {
            std::lock_guard<std::mutex> lk(m);
            done = true;
        }
        cv.notify_all();
    }
};

MrptCapture::MrptCapture(const MrptCaptureOptions& o) : s_(std::make_shared<Shared>())
{
    auto& s = *s_;
    s.o = o;
    const auto& c = o.camera;
    if (!c.registration)
        throw std::runtime_error("--capture mrpt: MRPT's COpenNI2Sensor always asks the device for depth-to-colour "
                                 "registration (--no-registration needs --capture openni2)");
    // MRPT opens devices by their position in OpenNI2's enumeration (or by an integer serial):
    // the device is found by index, serial or URI as for the openni2 backend, and opened by index.
    s.uri = resolveOniDevice(c.device, &s.index);
    if (s.index < 0)
        throw std::runtime_error(fmt::format("--capture mrpt: '{}' is not among the devices OpenNI2 enumerates; MRPT's "
                                             "COpenNI2Sensor opens only those (pndt-live --list-devices)",
                                             c.device));
    std::string text;
    if (!o.ini.empty())
    {
        std::ifstream in(o.ini);
        if (!in) throw std::runtime_error(o.ini + ": cannot open (--mrpt-config)");
        std::stringstream ss;
        ss << in.rdbuf();
        text = ss.str();
    }
    mrpt::config::CConfigFileMemory cfg(text);
    const std::string& sec = o.section;
    cfg.write(sec, "driver", "COpenNI2Sensor");
    cfg.write(sec, "sensorLabel", c.sensor_label);
    cfg.write(sec, "width", c.width);
    cfg.write(sec, "height", c.height);
    cfg.write(sec, "fps", c.fps);
    cfg.write(sec, "device_number", s.index);
    cfg.write(sec, "serial_number", 0);
    cfg.write(sec, "grab_image", true);
    cfg.write(sec, "grab_depth", true);
    cfg.write(sec, "grab_3D_points", false);
    cfg.write(sec, "preview_window", false);
    const bool calibrated = cfg.sectionExists(sec + "_LEFT");

    s.sensor = std::make_unique<mrpt::hwdrivers::COpenNI2Sensor>();
    {
        CoutCapture quiet;
        try
        {
            s.sensor->loadConfig(cfg, sec);
            s.sensor->initialize();
        }
        catch (const std::exception& e)
        {
            throw std::runtime_error(fmt::format("OpenNI2 device '{}' through MRPT's COpenNI2Sensor: {} (is a "
                                                 "{}x{}@{} depth + RGB888 colour mode there? MRPT_HWDRIVERS_VERBOSE=1 "
                                                 "shows MRPT's open sequence)",
                                                 s.uri, app::plainErrorText(e.what()), c.width, c.height, c.fps));
        }
        if (!s.sensor->isOpen(unsigned(s.index)))
            throw std::runtime_error(fmt::format("OpenNI2 device '{}' through MRPT's COpenNI2Sensor: not opened ({})",
                                                 s.uri, quiet.text()));
    }
    if (c.K)
    {
        s.K = *c.K;
        s.k_source = "--intrinsics";
    }
    else
    {
        const auto& p = s.sensor->getCameraParamsDepth();
        s.K = CameraIntrinsics{int(p.ncols), int(p.nrows), p.fx(), p.fy(), p.cx(), p.cy()};
        s.k_source = calibrated ? fmt::format("[{}_LEFT] of {}", sec, o.ini) : "the depth stream's fields of view";
        if (!(std::isfinite(s.K.fx) && std::isfinite(s.K.fy) && s.K.fx > 0 && s.K.fy > 0) || s.K.width != c.width ||
            s.K.height != c.height)
            throw std::runtime_error(fmt::format(
                "OpenNI2 device '{}' through MRPT's COpenNI2Sensor: no usable intrinsics from {} ({}x{}, fx {} fy {}); "
                "give --intrinsics 'fx fy cx cy' or a [{}_LEFT] calibration in --mrpt-config",
                s.uri, s.k_source, p.ncols, p.nrows, p.fx(), p.fy(), sec));
    }
    s.watch = std::make_unique<OniDisconnectWatch>(s.uri);
    s.thread = std::thread([keep = s_] { keep->run(); });
}

MrptCapture::~MrptCapture()
{
    auto& s = *s_;
    s.stop = true;
    s.watch.reset();
    std::unique_lock<std::mutex> lk(s.m);
    // A frame is due within 1/fps; a device that stopped streaming never returns.
    if (s.cv.wait_for(lk, std::chrono::seconds(1), [&] { return s.done; }))
    {
        lk.unlock();
        s.thread.join();
        s.sensor.reset();
        return;
    }
    lk.unlock();
    // Blocked in OpenNI2's readFrame without a timeout: leave the thread (and, through its
    // shared_ptr, the sensor it reads) behind.
    g_abandoned = true;
    s.thread.detach();
}

bool MrptCapture::abandoned() { return g_abandoned; }

std::optional<CapturedFrame> MrptCapture::grab(double timeout_s)
{
    auto& s = *s_;
    using clock = std::chrono::steady_clock;
    const clock::time_point deadline =
        clock::now() + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(timeout_s));
    std::optional<clock::time_point> gone_at;
    std::unique_lock<std::mutex> lk(s.m);
    for (;;)
    {
        if (!s.q.empty())
        {
            CapturedFrame f = std::move(s.q.front());
            s.q.pop_front();
            return f;
        }
        if (s.done) return std::nullopt;
        const auto now = clock::now();
        // After a disconnect, frames on their way are still taken (a short grace period).
        if (!gone_at && s.watch && s.watch->gone()) gone_at = now;
        if (gone_at && now - *gone_at > std::chrono::milliseconds(100)) return std::nullopt;
        if (now >= deadline) return std::nullopt;
        s.cv.wait_until(lk, std::min(deadline, now + std::chrono::milliseconds(20)));
    }
}

void MrptCapture::stopCapture() { s_->stop = true; }

bool MrptCapture::disconnected() const { return s_->watch && s_->watch->gone(); }

std::string MrptCapture::lostReason() const
{
    std::lock_guard<std::mutex> lk(s_->m);
    return s_->error;
}

uint64_t MrptCapture::replaced() const
{
    std::lock_guard<std::mutex> lk(s_->m);
    return s_->replaced;
}

const CameraIntrinsics& MrptCapture::intrinsics() const { return s_->K; }

std::string MrptCapture::describe() const
{
    const auto& s = *s_;
    return fmt::format("{} (device {}) through MRPT's COpenNI2Sensor, {}x{} @ {} Hz, fx {:.1f} fy {:.1f} from {}; "
                       "frames stamped with the host clock at grab",
                       s.uri, s.index, s.o.camera.width, s.o.camera.height, s.o.camera.fps, s.K.fx, s.K.fy,
                       s.k_source);
}

}  // namespace pndt::live
