#include <fmt/format.h>
#include <mrpt/io/CStream.h>
#include <mrpt/serialization/CArchive.h>
#include <pndt/app/gz_rawlog_file.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstring>
#include <filesystem>
#include <optional>

namespace pndt::app
{
namespace
{
gzFile handle(void* p) { return static_cast<gzFile>(p); }

/// The "NNNN" of a numbered file's name (numberedRawlogPath: four digits or more).
bool isFileNumber(const std::string& s)
{
    return s.size() >= 4 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

std::string gzMessage(void* gz)
{
    int code = 0;
    const char* m = gzerror(handle(gz), &code);
    return code == Z_ERRNO ? std::strerror(errno) : std::string(m ? m : "zlib error");
}
}  // namespace

/// The gzip file as an MRPT output stream (MRPT's CFileGZOutputStream cannot flush).
/// MRPT's archive rethrows what Write() throws as its own exception, so the sink keeps
/// the WriteError for write() to report as it is.
class GzRawlogFile::Sink : public mrpt::io::CStream
{
   public:
    Sink(void* gz, const std::string& path) : gz_(gz), path_(path) {}
    size_t Write(const void* buffer, size_t count) override
    {
        const auto* p = static_cast<const char*>(buffer);
        size_t done = 0;
        while (done < count)
        {
            const unsigned chunk = unsigned(std::min<size_t>(count - done, size_t(INT_MAX) / 2));
            const int put = gzwrite(handle(gz_), p + done, chunk);
            if (put <= 0)
            {
                failure = io::WriteError(fmt::format("cannot write {}: {}", path_, gzMessage(gz_)));
                throw *failure;
            }
            done += size_t(put);
        }
        return count;
    }
    size_t Read(void*, size_t) override { throw std::logic_error(path_ + ": write-only"); }
    uint64_t Seek(int64_t, CStream::TSeekOrigin) override { throw std::logic_error(path_ + ": cannot seek"); }
    uint64_t getTotalBytesCount() const override { return 0; }
    uint64_t getPosition() const override { return 0; }

    std::optional<io::WriteError> failure;

   private:
    void* gz_;
    const std::string& path_;
};

GzRawlogFile::GzRawlogFile(std::string path, int compression) : path_(std::move(path))
{
    const std::string mode = fmt::format("wb{}", std::clamp(compression, 0, 9));
    gz_ = gzopen(path_.c_str(), mode.c_str());
    if (!gz_) throw io::WriteError(fmt::format("cannot create {}: {}", path_, std::strerror(errno)));
    sink_ = std::make_unique<Sink>(gz_, path_);
}

GzRawlogFile::~GzRawlogFile()
{
    if (gz_) gzclose(handle(gz_));
}

void GzRawlogFile::write(const mrpt::serialization::CSerializable& obj)
{
    if (!gz_) throw std::logic_error(path_ + ": written after close()");
    try
    {
        auto archive = mrpt::serialization::archiveFrom(*sink_);
        archive << obj;
    }
    catch (...)
    {
        if (sink_->failure) throw *sink_->failure;  // MRPT's wrapper would hide the reason
        throw;
    }
    // Complete objects are on disk: a crash leaves a readable prefix.
    if (gzflush(handle(gz_), Z_SYNC_FLUSH) != Z_OK)
        throw io::WriteError(fmt::format("cannot write {}: {}", path_, gzMessage(gz_)));
    const z_off_t at = gzoffset(handle(gz_));
    if (at >= 0) bytes_ = uint64_t(at);
}

void GzRawlogFile::close()
{
    if (!gz_) return;
    const int rc = gzclose(handle(gz_));
    gz_ = nullptr;
    if (rc != Z_OK)
        throw io::WriteError(fmt::format("cannot close {}: {}", path_, rc == Z_ERRNO ? std::strerror(errno) : "zlib error"));
    std::error_code ec;
    const auto size = std::filesystem::file_size(path_, ec);  // with the trailer
    if (!ec) bytes_ = size;
}

std::string numberedRawlogPath(const std::string& path, size_t k)
{
    const std::filesystem::path p(path);
    return (p.parent_path() / fmt::format("{}-{:04d}{}", p.stem().string(), k, p.extension().string())).string();
}

std::vector<std::string> numberedRawlogsOf(const std::string& path)
{
    const std::filesystem::path p(path);
    const std::filesystem::path folder = p.parent_path().empty() ? "." : p.parent_path();
    const std::string stem = p.stem().string() + "-", ext = p.extension().string();
    std::vector<std::string> found;
    std::error_code ec;
    for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    {
        const std::string name = it->path().filename().string();
        if (name.size() < stem.size() + ext.size() || name.compare(0, stem.size(), stem) != 0 ||
            name.compare(name.size() - ext.size(), ext.size(), ext) != 0)
            continue;
        if (isFileNumber(name.substr(stem.size(), name.size() - stem.size() - ext.size())))
            found.push_back((p.parent_path() / name).string());
    }
    std::sort(found.begin(), found.end());
    return found;
}

bool sameRawlogFamily(const std::string& a, const std::string& b)
{
    namespace fs = std::filesystem;
    // Name without a "-NNNN" number before the extension.
    const auto family = [](const std::string& path) {
        std::error_code ec;
        fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
        if (ec) p = fs::absolute(path).lexically_normal();
        std::string stem = p.stem().string();
        const size_t dash = stem.rfind('-');
        if (dash != std::string::npos && isFileNumber(stem.substr(dash + 1))) stem.resize(dash);
        return (p.parent_path() / (stem + p.extension().string())).string();
    };
    return family(a) == family(b);
}

}  // namespace pndt::app
