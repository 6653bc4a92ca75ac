// Pose stream sources of pndt-live: line parsing, ordering, TCP reconnects, UDP, file tail.
#include <gtest/gtest.h>
#include <mrpt/system/datetime.h>
#include <pndt/live/pose_stream.h>
#include <pndt/mrpt/observation_frame.h>
#include <fmt/format.h>

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <fstream>
#include <thread>

using namespace pndt;
using namespace pndt::live;

namespace
{
int connectLocal(int port, int type = SOCK_STREAM)
{
    const int fd = ::socket(AF_INET, type, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(uint16_t(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    return fd;
}
void sendAll(int fd, const std::string& s) { ASSERT_EQ(::send(fd, s.data(), s.size(), 0), ssize_t(s.size())); }
bool waitCount(const LivePoseBuffer& b, uint64_t n)
{
    for (int i = 0; i < 300 && b.received() < n; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return b.received() >= n;
}
}  // namespace

TEST(PoseLine, ParsesTumAndRtabmap11AndNamesBadLines)
{
    const auto p = parsePoseLine("1.5 1 2 3 0 0 0 1", LineFormat::Tum, "x");
    ASSERT_TRUE(p);
    EXPECT_DOUBLE_EQ(p->t, 1.5);
    EXPECT_DOUBLE_EQ(p->T_world_sensor.translation().y(), 2.0);
    const auto q = parsePoseLine("2 1 2 3 0 0 0 1 42", LineFormat::Rtabmap11, "x");
    ASSERT_TRUE(q);
    EXPECT_EQ(q->id, 42);
    EXPECT_FALSE(parsePoseLine("#timestamp x y z qx qy qz qw id", LineFormat::Rtabmap11, "x"));
    try
    {
        parsePoseLine("2 1 2 3 0 0 0 1 42", LineFormat::Tum, "TCP 1.2.3.4:5 (line 7)");
        FAIL();
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("TCP 1.2.3.4:5 (line 7): expected 8 values"), std::string::npos) << e.what();
    }
    EXPECT_THROW(parsePoseLine("1 0 0 0 0 0 0 0", LineFormat::Tum, "x"), InputError);  // zero quaternion
    EXPECT_THROW(parseLineFormat("kml"), InputError);
}

TEST(LivePoseBuffer, DropsPosesNotAfterTheLastAndAppliesTheClockOffset)
{
    LivePoseBuffer b("P", 10.0);
    io::StampedPose p;
    p.t = 1.0;
    b.add(p, app::PoseFrame::Robot);
    b.add(p, app::PoseFrame::Robot);  // repeated (a reconnecting localiser)
    p.t = 0.5;
    b.add(p, app::PoseFrame::Robot);
    p.t = 2.0;
    b.add(p, app::PoseFrame::Robot);
    EXPECT_EQ(b.received(), 2u);
    EXPECT_EQ(b.droppedOutOfOrder(), 2u);
    EXPECT_NEAR(b.latest(), 12.0, 1e-6);
    const auto got = b.take();
    ASSERT_EQ(got.size(), 2u);
    EXPECT_NEAR(mrpt::Clock::toDouble(got[0]->timestamp), 11.0, 1e-6);
    EXPECT_EQ(got[0]->sensorLabel, "P");
    EXPECT_TRUE(b.take().empty());
    EXPECT_TRUE(b.waitFor(12.0, 0.0));
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_FALSE(b.waitFor(12.5, 0.2));
    EXPECT_GE(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.19);
}

TEST(LivePoseBuffer, CameraPosesBecomeRobotPosesWhoseCameraIsTheInput)
{
    LivePoseBuffer b;
    io::StampedPose p;
    p.t = 3;
    p.T_world_sensor = Pose::Identity();
    p.T_world_sensor.translation() << 1, 2, 3;
    p.T_world_sensor.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    b.add(p, app::PoseFrame::Camera);
    const auto got = b.take();
    ASSERT_EQ(got.size(), 1u);
    const Pose back = cameraPoseInWorld(got[0]->pose.mean, mrpt::poses::CPose3D());
    EXPECT_LT((back.matrix() - p.T_world_sensor.matrix()).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(PoseSources, TcpTakesLinesAcrossReconnectsAndCountsBadLines)
{
    LivePoseBuffer b;
    int port = 0;
    auto src = tcpPoseServer(0, LineFormat::Rtabmap11, app::PoseFrame::Robot, b, &port);
    ASSERT_GT(port, 0);
    int fd = connectLocal(port);
    sendAll(fd, "#timestamp x y z qx qy qz qw id\n1 0 0 0 0 0 0 1 1\n2 0 0 0 0 0 0 1 2\nnot a pose\n3 0 0");
    ASSERT_TRUE(waitCount(b, 2));
    ::close(fd);  // the half line "3 0 0" is lost with the connection
    fd = connectLocal(port);
    sendAll(fd, "3 1 0 0 0 0 0 1 3\n");
    ASSERT_TRUE(waitCount(b, 3));
    ::close(fd);
    EXPECT_EQ(b.bad_lines.load(), 1u);
    EXPECT_EQ(b.connections.load(), 2u);
    EXPECT_NEAR(b.latest(), 3.0, 1e-6);
}

TEST(PoseSources, ALineLongerThan4kBytesClosesItsConnectionAndTheNextConnectionIsRead)
{
    // A sender of megabytes without a newline grew the line buffer without bound (144 MB in
    // 12 s, each receive rescanning it): now the connection is closed at 4 kB.
    LivePoseBuffer b;
    int port = 0;
    auto src = tcpPoseServer(0, LineFormat::Rtabmap11, app::PoseFrame::Robot, b, &port);
    int fd = connectLocal(port);
    sendAll(fd, "1 0 0 0 0 0 0 1 1\n");
    ASSERT_TRUE(waitCount(b, 1));
    const std::string junk(3000, '9');
    bool closed = false;
    for (int i = 0; i < 2000 && !closed; ++i)  // until the server has closed it (send fails)
        closed = ::send(fd, junk.data(), junk.size(), MSG_NOSIGNAL) < 0;
    EXPECT_TRUE(closed) << "the connection stayed open after 6 MB without a newline";
    ::close(fd);
    EXPECT_EQ(b.bad_lines.load(), 1u);
    fd = connectLocal(port);
    sendAll(fd, "2 0 0 0 0 0 0 1 2\n");
    EXPECT_TRUE(waitCount(b, 2));
    ::close(fd);
}

TEST(PoseSources, UdpDatagramsAndAFileBeingAppendedTo)
{
    LivePoseBuffer u;
    int port = 0;
    {
        // a free UDP port: bind a TCP listener on 0 to find one, then use it for UDP
        LivePoseBuffer tmp;
        auto probe = tcpPoseServer(0, LineFormat::Tum, app::PoseFrame::Camera, tmp, &port);
    }
    auto udp = udpPoseReceiver(port, LineFormat::Tum, app::PoseFrame::Camera, u);
    const int fd = connectLocal(port, SOCK_DGRAM);
    sendAll(fd, "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1");
    ASSERT_TRUE(waitCount(u, 2));
    ::close(fd);

    const auto path = std::filesystem::temp_directory_path() / ("pndt_tail_" + std::to_string(::getpid()) + ".txt");
    std::filesystem::remove(path);
    LivePoseBuffer f;
    auto tail = tailPoseFile(path.string(), LineFormat::Tum, app::PoseFrame::Camera, f);  // the file comes later
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    {
        std::ofstream out(path);
        out << "1 0 0 0 0 0 0 1\n2 0 0 0";
    }
    ASSERT_TRUE(waitCount(f, 1));
    {
        std::ofstream out(path, std::ios::app);
        out << " 0 0 0 1\n";  // the line completed by a later write
    }
    ASSERT_TRUE(waitCount(f, 2));
    EXPECT_EQ(f.bad_lines.load(), 0u);
    tail.reset();
    std::filesystem::remove(path);
}

namespace
{
/// A grabber .ini with section [POSES] for the test plug-in's PndtTestPoseGrabber.
std::filesystem::path grabberIni(const std::string& name, const std::string& keys)
{
    const auto dir = std::filesystem::temp_directory_path() / ("pndt_grabber_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "poses.tum") << "# t x y z qx qy qz qw\n"
                                        "1.0 1 2 3 0 0 0 1\n"
                                        "1.5 1.5 2 3 0 0 0.2588190451 0.9659258263\n"
                                        "2.0 2 2 3 0 0 0.5 0.8660254038\n";
    const auto ini = dir / name;
    std::ofstream(ini) << "[POSES]\n" << keys << "file = " << (dir / "poses.tum").string() << "\n";
    return ini;
}
std::string errorOf(const std::function<void()>& f)
{
    try
    {
        f();
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return "(no error)";
}
}  // namespace

TEST(PoseSources, MrptGrabberRobotPosesFromAPluginSensorClass)
{
    const auto ini = grabberIni("ok.ini", fmt::format("driver = PndtTestPoseGrabber\nplugin = {}\nrate = 20\n",
                                                      PNDT_POSE_GRABBER_PLUGIN));
    LivePoseBuffer b("LIVE_POSE", 100.0);  // localiser clock + 100 s = frame clock
    auto src = mrptGrabberPoses(ini.string(), "POSES", b);
    EXPECT_NE(src->describe().find("[POSES]"), std::string::npos) << src->describe();
    ASSERT_TRUE(waitCount(b, 3));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    src.reset();
    EXPECT_EQ(b.received(), 3u);  // the CObservationComments in between are not poses
    EXPECT_EQ(b.bad_lines.load(), 0u);
    EXPECT_NEAR(b.latest(), 102.0, 1e-6);
    const auto got = b.take();
    ASSERT_EQ(got.size(), 3u);
    EXPECT_EQ(got[0]->sensorLabel, "LIVE_POSE");
    EXPECT_NEAR(mrpt::Clock::toDouble(got[1]->timestamp), 101.5, 1e-6);
    // The grabber's robot poses are taken as they are: their camera is the TUM file's.
    const Pose cam = cameraPoseInWorld(got[2]->pose.mean, mrpt::poses::CPose3D());
    EXPECT_NEAR(cam.translation().x(), 2.0, 1e-9);
    EXPECT_NEAR(cam.translation().z(), 3.0, 1e-9);
    const Eigen::Quaterniond q(cam.linear());
    EXPECT_NEAR(std::abs(q.dot(Eigen::Quaterniond(0.8660254038, 0, 0, 0.5))), 1.0, 1e-9);
}

TEST(PoseSources, MrptGrabberErrorsNameTheFileAndSection)
{
    LivePoseBuffer b;
    const auto plugin = std::string("plugin = ") + PNDT_POSE_GRABBER_PLUGIN + "\n";
    std::string e = errorOf([&] { mrptGrabberPoses("/nonexistent/grabber.ini", "POSES", b); });
    EXPECT_NE(e.find("/nonexistent/grabber.ini [POSES]: cannot open"), std::string::npos) << e;
    auto ini = grabberIni("nodriver.ini", plugin);
    e = errorOf([&] { mrptGrabberPoses(ini.string(), "POSES", b); });
    EXPECT_NE(e.find("[POSES]: no 'driver' key"), std::string::npos) << e;
    ini = grabberIni("unknown.ini", "driver = CNoSuchSensor\n");
    e = errorOf([&] { mrptGrabberPoses(ini.string(), "POSES", b); });
    EXPECT_NE(e.find("MRPT knows no sensor class 'CNoSuchSensor'"), std::string::npos) << e;
    EXPECT_NE(e.find("plugin"), std::string::npos) << e;
    ini = grabberIni("badplugin.ini", "driver = PndtTestPoseGrabber\nplugin = /nonexistent/libnothing.so\n");
    e = errorOf([&] { mrptGrabberPoses(ini.string(), "POSES", b); });
    EXPECT_NE(e.find("plugin '/nonexistent/libnothing.so' did not load"), std::string::npos) << e;
    ini = grabberIni("fails.ini", "driver = PndtTestPoseGrabber\nfail_initialize = true\n" + plugin);
    e = errorOf([&] { mrptGrabberPoses(ini.string(), "POSES", b); });
    EXPECT_NE(e.find(ini.string() + " [POSES]: PndtTestPoseGrabber did not initialise"), std::string::npos) << e;
    EXPECT_NE(e.find("told to fail"), std::string::npos) << e;
    EXPECT_EQ(b.received(), 0u);
}
