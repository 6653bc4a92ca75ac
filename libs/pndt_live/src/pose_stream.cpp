#include <fmt/format.h>
#include <mrpt/system/datetime.h>
#include <pndt/app/error_text.h>
#include <pndt/io/pose_line.h>
#include <pndt/live/pose_stream.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/system/os.h>
#include <pndt/mrpt/observation_frame.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <list>

namespace pndt::live
{
LineFormat parseLineFormat(const std::string& name)
{
    if (name == "tum") return LineFormat::Tum;
    if (name == "rtabmap10") return LineFormat::Rtabmap10;
    if (name == "rtabmap11" || name == "rtabmap") return LineFormat::Rtabmap11;
    throw InputError(fmt::format("pose stream format '{}' is not tum, rtabmap10 or rtabmap11", name));
}

std::optional<io::StampedPose> parsePoseLine(const std::string& line, LineFormat f, const std::string& where)
{
    return io::parseStampedPoseLine(line, f == LineFormat::Rtabmap11, where);
}

void LivePoseBuffer::add(const io::StampedPose& p, app::PoseFrame frame)
{
    auto o = std::make_shared<mrpt::obs::CObservationRobotPose>();
    o->sensorLabel = label_;
    o->timestamp = mrpt::Clock::fromDouble(p.t + offset_);
    // Robot frame as pndt-map's rawlog pose track expects it (scans' sensorPose is identity).
    o->pose.mean = frame == app::PoseFrame::Camera ? mrptSensorPoseOf(p.T_world_sensor) : toMrpt(p.T_world_sensor);
    push(std::move(o));
}

void LivePoseBuffer::add(const mrpt::obs::CObservationRobotPose& p)
{
    auto o = std::make_shared<mrpt::obs::CObservationRobotPose>(p);
    o->sensorLabel = label_;
    if (offset_ != 0) o->timestamp = mrpt::Clock::fromDouble(mrpt::Clock::toDouble(p.timestamp) + offset_);
    push(std::move(o));
}

void LivePoseBuffer::push(mrpt::obs::CObservationRobotPose::Ptr p)
{
    // What a reader of the recording gets back (CPose3D is stored as a quaternion): the live
    // map uses exactly the numbers a replay of the recording will use.
    {
        mrpt::io::CMemoryStream buf;
        auto a = mrpt::serialization::archiveFrom(buf);
        a << *p;
        buf.Seek(0);
        p = std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(a.ReadObject());
    }
    // Stamps go through mrpt::Clock (100 ns ticks): compare what the track will see.
    const double t = mrpt::Clock::toDouble(p->timestamp);
    {
        std::lock_guard<std::mutex> lk(m_);
        if (!(t > latest_))
        {
            ++out_of_order_;
            return;
        }
        latest_ = t;
        fresh_.push_back(std::move(p));
        ++received_;
    }
    cv_.notify_all();
}

bool LivePoseBuffer::waitFor(double t, double max_wait_s)
{
    std::unique_lock<std::mutex> lk(m_);
    return cv_.wait_for(lk, std::chrono::duration<double>(std::max(0.0, max_wait_s)),
                        [&] { return stopped_ || latest_ >= t; }) &&
           latest_ >= t;
}

std::vector<mrpt::obs::CObservationRobotPose::Ptr> LivePoseBuffer::take()
{
    std::lock_guard<std::mutex> lk(m_);
    std::vector<mrpt::obs::CObservationRobotPose::Ptr> out(fresh_.begin(), fresh_.end());
    fresh_.clear();
    return out;
}

double LivePoseBuffer::latest() const
{
    std::lock_guard<std::mutex> lk(m_);
    return latest_;
}

void LivePoseBuffer::stop()
{
    {
        std::lock_guard<std::mutex> lk(m_);
        stopped_ = true;
    }
    cv_.notify_all();
}

namespace
{
/// Splits received bytes into lines and feeds them to the buffer.
struct LineFeeder
{
    LineFormat format;
    app::PoseFrame frame;
    LivePoseBuffer* buffer;
    std::string where;
    std::string partial{};  // a line not ended yet
    uint64_t line_no = 0;
    /// A pose line is under 200 bytes: a sender of megabytes without a newline is broken or
    /// hostile (the buffer grew without bound, rescanned on every receive).
    static constexpr size_t kMaxLine = 4096;

    /// False after a line longer than kMaxLine (said once, naming the source): the caller
    /// closes the connection; what was buffered is dropped.
    bool bytes(const char* p, size_t n)
    {
        size_t start = 0, nl, from = partial.size();  // bytes before `from` hold no newline
        partial.append(p, n);
        while ((nl = partial.find('\n', from)) != std::string::npos)
        {
            line(partial.substr(start, nl - start));
            start = from = nl + 1;
        }
        partial.erase(0, start);
        if (partial.size() <= kMaxLine) return true;
        fmt::print(stderr, "pndt-live: pose stream {}: line {} is longer than {} bytes without a newline: {}\n", where,
                   line_no + 1, kMaxLine, closing_note);
        partial.clear();
        ++buffer->bad_lines;
        return false;
    }
    const char* closing_note = "connection closed";
    void line(const std::string& l)
    {
        ++line_no;
        try
        {
            if (auto p = parsePoseLine(l, format, fmt::format("{} (line {})", where, line_no))) buffer->add(*p, frame);
        }
        catch (const std::exception& e)
        {
            if (buffer->bad_lines++ < 5) fmt::print(stderr, "pndt-live: pose ignored: {}\n", e.what());
        }
    }
};

class SocketSource : public PoseSource
{
   public:
    SocketSource(bool tcp, int port, LineFormat f, app::PoseFrame frame, LivePoseBuffer& b, int* bound)
        : tcp_(tcp), f_(f), frame_(frame), b_(b)
    {
        fd_ = ::socket(AF_INET, tcp ? SOCK_STREAM : SOCK_DGRAM, 0);
        if (fd_ < 0) throw std::runtime_error(fmt::format("pose stream: socket(): {}", std::strerror(errno)));
        int one = 1;
        ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_ANY);
        a.sin_port = htons(uint16_t(port));
        if (::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || (tcp && ::listen(fd_, 8) != 0))
        {
            const std::string err = std::strerror(errno);
            ::close(fd_);
            throw std::runtime_error(fmt::format("pose stream: cannot listen on {} port {}: {}", tcp ? "TCP" : "UDP",
                                                 port, err));
        }
        socklen_t len = sizeof a;
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
        port_ = ntohs(a.sin_port);
        if (bound) *bound = port_;
        thread_ = std::thread([this] { run(); });
    }
    ~SocketSource() override
    {
        stop_ = true;
        thread_.join();
        ::close(fd_);
    }
    std::string describe() const override
    {
        return fmt::format("{} port {}", tcp_ ? "TCP" : "UDP", port_);
    }

   private:
    struct Conn
    {
        int fd;
        LineFeeder feeder;
    };
    void run()
    {
        std::list<Conn> conns;
        LineFeeder udp{f_, frame_, &b_, fmt::format("UDP port {}", port_)};
        udp.closing_note = "datagram dropped";
        char buf[65536];
        while (!stop_)
        {
            std::vector<pollfd> fds{{fd_, POLLIN, 0}};
            for (auto& c : conns) fds.push_back({c.fd, POLLIN, 0});
            if (::poll(fds.data(), fds.size(), 100) <= 0) continue;
            if (fds[0].revents & POLLIN)
            {
                if (tcp_)
                {
                    sockaddr_in peer{};
                    socklen_t len = sizeof peer;
                    const int c = ::accept(fd_, reinterpret_cast<sockaddr*>(&peer), &len);
                    if (c >= 0)
                    {
                        ++b_.connections;
                        ++b_.open_connections;
                        conns.push_back({c, LineFeeder{f_, frame_, &b_,
                                                       fmt::format("TCP {}:{}", inet_ntoa(peer.sin_addr),
                                                                   ntohs(peer.sin_port))}});
                    }
                }
                else
                {
                    const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
                    if (n > 0)
                    {
                        // A datagram ends its last line; an over-long one is dropped.
                        if (udp.bytes(buf, size_t(n)) && !udp.partial.empty()) udp.bytes("\n", 1);
                    }
                }
            }
            // Only the connections polled above have an entry in fds: one accepted just now
            // is at the back of conns and waits for the next poll (found by ASan: fds was read
            // one past its end, a garbage revents, then a blocking recv).
            const size_t polled = fds.size();
            size_t i = 1;
            for (auto it = conns.begin(); it != conns.end() && i < polled; ++i)
            {
                if (fds[i].revents & (POLLIN | POLLHUP | POLLERR))
                {
                    const ssize_t n = ::recv(it->fd, buf, sizeof buf, 0);
                    if (n <= 0 || !it->feeder.bytes(buf, size_t(n)))  // closed, or a line too long
                    {
                        ::close(it->fd);
                        --b_.open_connections;
                        it = conns.erase(it);
                        continue;
                    }
                }
                ++it;
            }
        }
        for (auto& c : conns) ::close(c.fd);
    }

    bool tcp_;
    LineFormat f_;
    app::PoseFrame frame_;
    LivePoseBuffer& b_;
    int fd_ = -1, port_ = 0;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

class TailSource : public PoseSource
{
   public:
    TailSource(std::string path, LineFormat f, app::PoseFrame frame, LivePoseBuffer& b)
        : path_(std::move(path)), feeder_{f, frame, &b, path_}
    {
        feeder_.closing_note = "skipped";
        thread_ = std::thread([this] { run(); });
    }
    ~TailSource() override
    {
        stop_ = true;
        thread_.join();
    }
    std::string describe() const override { return "file " + path_ + " (followed)"; }

   private:
    void run()
    {
        std::ifstream in;
        char buf[65536];
        while (!stop_)
        {
            if (!in.is_open())
            {
                in.open(path_, std::ios::binary);
                if (!in.is_open())
                {
                    std::this_thread::sleep_for(std::chrono::milliseconds(50));
                    continue;
                }
            }
            in.read(buf, sizeof buf);
            const auto n = in.gcount();
            if (n > 0 && !feeder_.bytes(buf, size_t(n)))
            {
                in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');  // on after the long line
                in.clear();
            }
            if (in.eof())
            {
                in.clear();  // more may be appended
                std::this_thread::sleep_for(std::chrono::milliseconds(20));
            }
        }
    }
    std::string path_;
    LineFeeder feeder_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};
class GrabberSource : public PoseSource
{
   public:
    GrabberSource(const std::string& ini, const std::string& section, LivePoseBuffer& b) : b_(b)
    {
        where_ = fmt::format("{} [{}]", ini, section);
        if (!std::ifstream(ini)) throw std::runtime_error(where_ + ": cannot open");
        mrpt::config::CConfigFile cfg(ini);
        const std::string driver = cfg.read_string(section, "driver", "");
        if (driver.empty()) throw std::runtime_error(where_ + ": no 'driver' key (the MRPT sensor class)");
        // MRPT's own sensor classes give no CObservationRobotPose: the class producing them is
        // usually the user's own, in a plug-in module (comma-separated list) registering it.
        const std::string plugin = cfg.read_string(section, "plugin", "");
        if (!plugin.empty())
        {
            std::string errors;
            if (!mrpt::system::loadPluginModules(plugin, errors))
                throw std::runtime_error(fmt::format("{}: plugin '{}' did not load: {}", where_, plugin, errors));
        }
        sensor_ = mrpt::hwdrivers::CGenericSensor::createSensorPtr(driver);
        if (!sensor_)
            throw std::runtime_error(fmt::format("{}: MRPT knows no sensor class '{}' (a class of your own: name its "
                                                 "module in the key plugin = lib.so)",
                                                 where_, driver));
        try
        {
            sensor_->loadConfig(cfg, section);
            sensor_->initialize();
        }
        catch (const std::exception& e)
        {
            throw std::runtime_error(
                fmt::format("{}: {} did not initialise: {}", where_, driver, app::plainErrorText(e.what())));
        }
        thread_ = std::thread([this] { run(); });
    }
    ~GrabberSource() override
    {
        stop_ = true;
        thread_.join();
    }
    std::string describe() const override { return "MRPT grabber " + where_; }

   private:
    void run()
    {
        while (!stop_)
        {
            try
            {
                sensor_->doProcess();
                mrpt::hwdrivers::CGenericSensor::TListObservations obs;
                sensor_->getObservations(obs);
                for (const auto& [t, o] : obs)
                    if (auto p = std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(o)) b_.add(*p);
            }
            catch (const std::exception& e)
            {
                if (b_.bad_lines++ < 5) fmt::print(stderr, "pndt-live: {}: {}\n", where_, e.what());
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    }
    LivePoseBuffer& b_;
    std::string where_;
    mrpt::hwdrivers::CGenericSensor::Ptr sensor_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};
}  // namespace

std::unique_ptr<PoseSource> mrptGrabberPoses(const std::string& ini, const std::string& section,
                                             LivePoseBuffer& buffer)
{
    return std::make_unique<GrabberSource>(ini, section, buffer);
}

std::unique_ptr<PoseSource> tcpPoseServer(int port, LineFormat f, app::PoseFrame frame, LivePoseBuffer& buffer,
                                          int* bound_port)
{
    return std::make_unique<SocketSource>(true, port, f, frame, buffer, bound_port);
}
std::unique_ptr<PoseSource> udpPoseReceiver(int port, LineFormat f, app::PoseFrame frame, LivePoseBuffer& buffer)
{
    return std::make_unique<SocketSource>(false, port, f, frame, buffer, nullptr);
}
std::unique_ptr<PoseSource> tailPoseFile(const std::string& path, LineFormat f, app::PoseFrame frame,
                                         LivePoseBuffer& buffer)
{
    return std::make_unique<TailSource>(path, f, frame, buffer);
}

}  // namespace pndt::live
