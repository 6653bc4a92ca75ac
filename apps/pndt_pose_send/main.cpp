// pndt-pose-send: replays a pose file (TUM or RTAB-Map 10/11 lines) onto pndt-live's pose
// stream over TCP or UDP, paced by its stamps or at a fixed rate; reconnects when the
// connection drops. For tests, demos and bridging a localiser that writes a file.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <pndt/app/cli_numbers.h>
#include <pndt/live/pose_stream.h>

#include <arpa/inet.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <thread>

using namespace pndt;

namespace
{
int connectTo(const std::string& host, int port, bool udp)
{
    addrinfo hints{}, *res = nullptr;
    hints.ai_family = AF_INET;
    hints.ai_socktype = udp ? SOCK_DGRAM : SOCK_STREAM;
    if (getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &res) != 0 || !res) return -1;
    const int fd = ::socket(res->ai_family, res->ai_socktype, 0);
    if (fd >= 0 && ::connect(fd, res->ai_addr, res->ai_addrlen) != 0)
    {
        ::close(fd);
        freeaddrinfo(res);
        return -1;
    }
    freeaddrinfo(res);
    return fd;
}
}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"pndt-pose-send: replay a pose file onto pndt-live's pose stream"};
    std::string file, to = "127.0.0.1:5555", format = "tum";
    double rate = -1, speed = 1, connect_timeout = 10, stamp_offset = 0;
    size_t max_poses = 0;
    bool udp = false;
    app.add_option("file", file, "pose file (TUM or RTAB-Map 10/11 lines)")->required()->check(CLI::ExistingFile);
    app.add_option("--to", to, "host:port of pndt-live --pose-tcp / --pose-udp")->capture_default_str();
    app.add_flag("--udp", udp, "send datagrams instead of a TCP stream");
    app.add_option("--format", format, "line format, checked before sending: tum, rtabmap10, rtabmap11")
        ->capture_default_str();
    app.add_option("--rate", rate, "poses per second (0 = as fast as possible); default: paced by the stamps")
        ->check(app::kNonNegative);
    app.add_option("--speed", speed, "with stamp pacing: replay speed factor")->capture_default_str()->check(app::kPositive);
    app.add_option("--stamp-offset", stamp_offset,
                   "seconds added to every stamp sent (e.g. device time -> host clock for pndt-live --capture mrpt)");
    app.add_option("--max-poses", max_poses, "stop after this many poses (a localiser that stops)");
    app.add_option("--connect-timeout", connect_timeout, "seconds to keep trying to (re)connect")->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    std::signal(SIGPIPE, SIG_IGN);
    try
    {
        const auto colon = to.rfind(':');
        if (colon == std::string::npos) throw std::runtime_error("--to '" + to + "' is not host:port");
        const std::string host = to.substr(0, colon);
        const std::string port_text = to.substr(colon + 1);
        const int port = port_text.find_first_not_of("0123456789") == std::string::npos && !port_text.empty() &&
                                 port_text.size() <= 5
                             ? std::stoi(port_text)
                             : -1;
        if (port < 1 || port > 65535) throw std::runtime_error("--to '" + to + "': the port must be 1-65535");
        const auto lf = live::parseLineFormat(format);
        // Read and check every line first: a bad file fails before anything is sent.
        std::ifstream in(file);
        std::vector<std::pair<double, std::string>> lines;
        std::string line;
        for (int n = 1; std::getline(in, line); ++n)
            if (auto p = live::parsePoseLine(line, lf, fmt::format("{} (line {})", file, n)))
            {
                if (stamp_offset != 0)  // the stamp (first field) replaced, the rest sent as read
                {
                    const auto b = line.find_first_not_of(" \t"), e = line.find_first_of(" \t,", b);
                    line = fmt::format("{:.6f}", p->t + stamp_offset) + line.substr(e);
                }
                lines.emplace_back(p->t, line + "\n");
            }
        if (max_poses > 0 && lines.size() > max_poses) lines.resize(max_poses);
        if (lines.empty()) throw std::runtime_error(file + ": no poses");

        int fd = -1;
        size_t sent = 0, reconnects = 0, refused = 0;
        const auto connect = [&] {
            const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(connect_timeout);
            while ((fd = connectTo(host, port, udp)) < 0)
            {
                if (std::chrono::steady_clock::now() > until)
                    throw std::runtime_error(
                        sent ? fmt::format("the receiver at {} went away after {} of {} poses and did not come back "
                                           "within {} s",
                                           to, sent, lines.size(), connect_timeout)
                             : fmt::format("cannot connect to {} for {} s", to, connect_timeout));
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
            }
        };
        connect();
        const auto t0 = std::chrono::steady_clock::now();
        for (size_t i = 0; i < lines.size(); ++i)
        {
            if (rate > 0)
                std::this_thread::sleep_until(t0 + std::chrono::duration<double>(double(i) / rate));
            else if (rate < 0 && speed > 0)
                std::this_thread::sleep_until(t0 + std::chrono::duration<double>((lines[i].first - lines[0].first) / speed));
            const std::string& l = lines[i].second;
            if (udp)
            {
                // A datagram is not sent again: one refused (nothing listening) is counted.
                if (::send(fd, l.data(), l.size(), MSG_NOSIGNAL) != ssize_t(l.size())) ++refused;
                ++sent;
                continue;
            }
            while (::send(fd, l.data(), l.size(), MSG_NOSIGNAL) != ssize_t(l.size()))
            {
                ::close(fd);  // the receiver went away: reconnect, send this pose again
                ++reconnects;
                connect();
            }
            ++sent;
        }
        ::close(fd);
        fmt::print("pndt-pose-send: {} poses sent to {} in {:.2f} s ({}{})\n", sent, to,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                   udp ? fmt::format("{} refused", refused) : fmt::format("{} reconnects", reconnects),
                   refused ? ": nothing listening there?" : "");
        if (udp && refused > 0 && refused * 4 >= sent)  // ICMP refusals arrive late: every other datagram at full rate
        {
            fmt::print(stderr, "pndt-pose-send: error: {} of {} datagrams to {} were refused (nothing listening?)\n",
                       refused, sent, to);
            return 1;
        }
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-pose-send: error: {}\n", e.what());
        return 1;
    }
    return 0;
}
