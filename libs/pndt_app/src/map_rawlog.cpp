#include <fmt/format.h>
#include <mrpt/system/datetime.h>
#include <pndt/app/map_rawlog.h>
#include <pndt/io/atomic_file.h>
#include <pndt/mrpt/CObservationPanopticMap.h>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>

namespace pndt::app
{
MapRawlogWriter::MapRawlogWriter(MapRawlogOptions options)
    : options_(std::move(options)), writer_(options_.max_queued, [this](Item& item) { write(item); })
{
    if (options_.keep_maps > 0 && options_.segment_maps == 0)
        throw std::invalid_argument("maps rawlog: keep_maps needs segment_maps (one file cannot drop its oldest maps)");
    // The first file is created with the first object (write()): a run that writes nothing
    // (stopped early, no frame mapped) leaves an earlier run's file as it was. A folder we
    // cannot write to is still reported at once.
    const std::filesystem::path folder = std::filesystem::path(options_.path).parent_path();
    const std::string dir = folder.empty() ? "." : folder.string();
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
        throw io::WriteError(fmt::format("cannot write {}: {}", options_.path, std::strerror(errno)));
}

std::string MapRawlogWriter::segmentPath(size_t k) const
{
    return options_.segment_maps == 0 ? options_.path : numberedRawlogPath(options_.path, k);
}

void MapRawlogWriter::openFile()
{
    std::string path;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        path = segmentPath(next_file_);
    }
    file_ = std::make_unique<GzRawlogFile>(path, options_.compression);
    std::lock_guard<std::mutex> lock(mutex_);
    ++next_file_;
}

void MapRawlogWriter::closeFile()
{
    const auto file = std::move(file_);
    file->close();
    std::lock_guard<std::mutex> lock(mutex_);
    closed_bytes_ += file->bytes();
}

void MapRawlogWriter::deleteOldFiles(uint64_t maps_done)
{
    if (options_.keep_maps == 0 || maps_done < options_.keep_maps) return;
    const uint64_t first_kept_map = maps_done - options_.keep_maps;
    const uint64_t S = options_.segment_maps;
    for (;;)
    {
        size_t k;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            k = first_kept_file_;
            // Only closed files: the last map of file k is (k + 1) S - 1.
            if (k + 1 >= next_file_ + (file_ ? 0 : 1) || (k + 1) * S > first_kept_map) return;
        }
        const std::string path = segmentPath(k);
        std::error_code ec;
        std::filesystem::remove(path, ec);  // a file already gone is fine
        if (ec) throw io::WriteError(fmt::format("cannot delete the old maps rawlog '{}': {}", path, ec.message()));
        std::lock_guard<std::mutex> lock(mutex_);
        ++first_kept_file_;
    }
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
    writer_.rethrowError();
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
    if (finished_) throw std::logic_error("MapRawlogWriter: object added after finish()");
    writer_.push({std::move(obj), is_map});  // after an error: dropped, reported by addMap() / finish()
}

void MapRawlogWriter::write(const Item& item)
{
    if (!file_) openFile();  // the file (the next segment) opened with its first object: no empty file
    file_->write(*item.first);
    if (item.second)
    {
        ++maps_done_;
        if (options_.segment_maps > 0 && maps_done_ % options_.segment_maps == 0) closeFile();
        deleteOldFiles(maps_done_);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    (item.second ? maps_ : inputs_) += 1;
    bytes_ = closed_bytes_ + (file_ ? file_->bytes() : 0);
}

void MapRawlogWriter::finish()
{
    if (!finished_)
    {
        while (!held_.empty())
        {
            enqueue(held_.front(), false);
            held_.pop_front();
        }
        finished_ = true;
        writer_.close();
        if (file_)
        {
            try
            {
                closeFile();
            }
            catch (...)
            {
                close_error_ = std::current_exception();
            }
        }
        std::lock_guard<std::mutex> lock(mutex_);
        bytes_ = closed_bytes_;  // every file with its trailer
    }
    writer_.rethrowError();
    if (close_error_) std::rethrow_exception(close_error_);
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
size_t MapRawlogWriter::filesWritten() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return next_file_;
}
size_t MapRawlogWriter::filesDeleted() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return first_kept_file_;
}
double MapRawlogWriter::secondsWriting() const { return writer_.secondsWriting(); }

std::string rawlogFilesNote(const MapRawlogWriter& w)
{
    const size_t files = w.filesWritten(), deleted = w.filesDeleted();
    if (!w.segmented() || files == 0) return {};
    namespace fs = std::filesystem;
    const auto name = [&](size_t k) { return fs::path(w.segmentPath(k)).filename().string(); };
    std::string note = files - deleted == 1 ? " in " + name(deleted)
                                            : fmt::format(" in {} .. {}", name(deleted), name(files - 1));
    if (deleted > 0) note += fmt::format("; the {} older files deleted", deleted);
    return note;
}

}  // namespace pndt::app
