#include <fmt/format.h>
#include <mrpt/io/CStream.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>
#include <pndt/app/map_rawlog.h>
#include <pndt/io/atomic_file.h>
#include <pndt/mrpt/CObservationPanopticMap.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstring>
#include <filesystem>
#include <optional>

namespace pndt::app
{
namespace
{
gzFile handle(void* p) { return static_cast<gzFile>(p); }

std::string gzMessage(void* gz)
{
    int code = 0;
    const char* m = gzerror(handle(gz), &code);
    return code == Z_ERRNO ? std::strerror(errno) : std::string(m ? m : "zlib error");
}

/// The gzip file as an MRPT output stream (MRPT's CFileGZOutputStream cannot flush).
/// MRPT's archive rethrows what Write() throws as its own exception, so the sink
/// keeps the WriteError for run() to report as it is.
class GzSink : public mrpt::io::CStream
{
   public:
    GzSink(void* gz, const std::string& path) : gz_(gz), path_(path) {}
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
                failure_ = io::WriteError(fmt::format("cannot write {}: {}", path_, gzMessage(gz_)));
                throw *failure_;
            }
            done += size_t(put);
        }
        return count;
    }
    size_t Read(void*, size_t) override { throw std::logic_error(path_ + ": write-only"); }
    uint64_t Seek(int64_t, CStream::TSeekOrigin) override { throw std::logic_error(path_ + ": cannot seek"); }
    uint64_t getTotalBytesCount() const override { return 0; }
    uint64_t getPosition() const override { return 0; }
    const std::optional<io::WriteError>& failure() const { return failure_; }

   private:
    void* gz_;
    std::string path_;
    std::optional<io::WriteError> failure_;
};
}  // namespace

MapRawlogWriter::MapRawlogWriter(MapRawlogOptions options) : options_(std::move(options))
{
    const std::string mode = fmt::format("wb{}", std::clamp(options_.compression, 0, 9));
    gz_ = gzopen(options_.path.c_str(), mode.c_str());
    if (!gz_) throw io::WriteError(fmt::format("cannot create {}: {}", options_.path, std::strerror(errno)));
    thread_ = std::thread([this] { run(); });
}

MapRawlogWriter::~MapRawlogWriter()
{
    try
    {
        finish();
    }
    catch (...)
    {
    }
}

void MapRawlogWriter::addInput(const mrpt::obs::CObservation::Ptr& obs)
{
    if (!obs) return;
    held_.push_back(obs);
    while (held_.size() > options_.max_held_inputs)
    {
        enqueue(held_.front(), false);
        held_.pop_front();
    }
}

void MapRawlogWriter::release(double t)
{
    // In arrival order: an input is written once every input before it was.
    while (!held_.empty() && mrpt::Clock::toDouble(held_.front()->timestamp) <= t)
    {
        enqueue(held_.front(), false);
        held_.pop_front();
    }
}

void MapRawlogWriter::mappedUpTo(double t) { release(t); }

void MapRawlogWriter::addMap(const PanopticNDTMap::Ptr& map, double t_start, double t_end, uint64_t frames,
                             uint32_t sequence)
{
    rethrowError();
    release(t_end);
    auto o = CObservationPanopticMap::Create();
    o->sensorLabel = options_.sensor_label;
    o->timestamp = mrpt::Clock::fromDouble(t_end);
    o->start = mrpt::Clock::fromDouble(t_start);
    o->frames = frames;
    o->sequence = sequence;
    o->map = map;
    enqueue(o, true);
}

void MapRawlogWriter::enqueue(mrpt::serialization::CSerializable::Ptr obj, bool is_map)
{
    std::unique_lock<std::mutex> lock(mutex_);
    if (finished_) throw std::logic_error("MapRawlogWriter: object added after finish()");
    cv_.wait(lock, [&] { return queue_.size() < options_.max_queued || error_; });
    if (error_) return;  // reported by addMap() / finish()
    queue_.emplace_back(std::move(obj), is_map);
    cv_.notify_all();
}

void MapRawlogWriter::run()
{
    GzSink sink(gz_, options_.path);
    auto archive = mrpt::serialization::archiveFrom(sink);
    for (;;)
    {
        std::pair<mrpt::serialization::CSerializable::Ptr, bool> item;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            cv_.wait(lock, [&] { return !queue_.empty() || closing_; });
            if (queue_.empty()) return;  // closing and drained
            item = std::move(queue_.front());
            queue_.pop_front();
            busy_ = true;
            cv_.notify_all();
        }
        const auto t0 = std::chrono::steady_clock::now();
        try
        {
            if (!error_)
            {
                archive << *item.first;
                // Complete objects are on disk: a crash leaves a readable prefix.
                if (gzflush(handle(gz_), Z_SYNC_FLUSH) != Z_OK)
                    throw io::WriteError(fmt::format("cannot write {}: {}", options_.path, gzMessage(gz_)));
            }
        }
        catch (...)
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!error_) error_ = sink.failure() ? std::make_exception_ptr(*sink.failure()) : std::current_exception();
        }
        const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::lock_guard<std::mutex> lock(mutex_);
        busy_ = false;
        seconds_ += dt;
        if (!error_)
        {
            (item.second ? maps_ : inputs_) += 1;
            const z_off_t at = gzoffset(handle(gz_));
            if (at >= 0) bytes_ = uint64_t(at);
        }
        cv_.notify_all();
    }
}

void MapRawlogWriter::finish()
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (finished_)
        {
            if (error_) std::rethrow_exception(error_);
            return;
        }
    }
    while (!held_.empty())
    {
        enqueue(held_.front(), false);
        held_.pop_front();
    }
    {
        std::lock_guard<std::mutex> lock(mutex_);
        finished_ = closing_ = true;
        cv_.notify_all();
    }
    if (thread_.joinable()) thread_.join();
    const int rc = gzclose(handle(gz_));
    gz_ = nullptr;
    std::lock_guard<std::mutex> lock(mutex_);
    std::error_code ec;
    if (const auto size = std::filesystem::file_size(options_.path, ec); !ec) bytes_ = size;  // with the trailer
    if (rc != Z_OK && !error_)
        error_ = std::make_exception_ptr(io::WriteError(fmt::format("cannot close {}", options_.path)));
    if (error_) std::rethrow_exception(error_);
}

void MapRawlogWriter::rethrowError()
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (error_) std::rethrow_exception(error_);
}

uint64_t MapRawlogWriter::mapsWritten() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return maps_;
}
uint64_t MapRawlogWriter::inputsWritten() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return inputs_;
}
uint64_t MapRawlogWriter::bytesWritten() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return bytes_;
}
double MapRawlogWriter::secondsWriting() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return seconds_;
}

}  // namespace pndt::app
