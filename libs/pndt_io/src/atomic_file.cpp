#include <pndt/io/atomic_file.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace pndt::io
{
namespace fs = std::filesystem;

namespace
{
[[noreturn]] void fail(const std::string& path, const std::string& what, int err)
{
    throw WriteError("cannot write '" + path + "': " + what + (err ? std::string(": ") + std::strerror(err) : ""));
}
}  // namespace

void closeWrittenStream(std::ofstream& f, const std::string& path)
{
    // A write that failed left its errno (the stream's later operations are no-ops);
    // otherwise the close writes what is buffered and sets errno if that fails.
    const bool failed = !f;
    const int err_before = errno;
    errno = 0;
    f.close();
    if (!failed && !f.fail()) return;
    const int err = failed ? err_before : errno;
    fail(path, "write failed", err);
}

void writeFileAtomically(const std::string& path, std::string_view bytes)
{
    if (path.empty()) throw WriteError("cannot write a file with an empty path");
    const fs::path target(path);
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::string tmpl = (dir / ("." + target.filename().string() + ".tmpXXXXXX")).string();
    std::vector<char> name(tmpl.begin(), tmpl.end());
    name.push_back('\0');
    const int fd = ::mkstemp(name.data());
    if (fd < 0) fail(path, "cannot create a temporary file in '" + dir.string() + "'", errno);
    const std::string tmp(name.data());
    auto abandon = [&](const std::string& what, int err) {
        ::close(fd);
        ::unlink(tmp.c_str());
        fail(path, what, err);
    };
    size_t done = 0;
    while (done < bytes.size())
    {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0)
        {
            if (errno == EINTR) continue;
            abandon("write failed", errno);
        }
        done += size_t(n);
    }
    // mkstemp creates 0600; results are meant to be shared: rw-r--r--. (Reading the umask
    // would need umask(), which is process-wide and racy.)
    if (::fchmod(fd, 0644) != 0) abandon("chmod failed", errno);
    if (::fsync(fd) != 0) abandon("fsync failed", errno);
    if (::close(fd) != 0)
    {
        const int err = errno;
        ::unlink(tmp.c_str());
        fail(path, "close failed", err);
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
    {
        const int err = errno;
        ::unlink(tmp.c_str());
        fail(path, "rename from '" + tmp + "' failed", err);
    }
}

void writeFileAtomically(const std::string& path, const std::function<void(const std::string&)>& write)
{
    if (path.empty()) throw WriteError("cannot write a file with an empty path");
    const fs::path target(path);
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::string tmpl = (dir / ("." + target.filename().string() + ".tmpXXXXXX")).string();
    std::vector<char> name(tmpl.begin(), tmpl.end());
    name.push_back('\0');
    const int fd = ::mkstemp(name.data());
    if (fd < 0) fail(path, "cannot create a temporary file in '" + dir.string() + "'", errno);
    ::close(fd);
    const std::string tmp(name.data());
    try
    {
        write(tmp);
        const int wfd = ::open(tmp.c_str(), O_RDONLY);
        if (wfd < 0) fail(path, "the writer left no file", errno);
        const bool synced = ::fchmod(wfd, 0644) == 0 && ::fsync(wfd) == 0;
        const int err = errno;
        ::close(wfd);
        if (!synced) fail(path, "chmod/fsync failed", err);
        if (std::rename(tmp.c_str(), path.c_str()) != 0) fail(path, "rename from '" + tmp + "' failed", errno);
    }
    catch (...)
    {
        ::unlink(tmp.c_str());
        throw;
    }
}

void ensureDirectory(const std::string& dir)
{
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw WriteError("cannot create folder '" + dir + "': " + ec.message());
    if (!fs::is_directory(dir)) throw WriteError("cannot create folder '" + dir + "': a file of that name exists");
}

}  // namespace pndt::io
