#include "recorder.h"

#include <fmt/format.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/system/datetime.h>
#include <pndt/io/atomic_file.h>

#include <filesystem>

namespace pndt::live
{
Recorder::Recorder(RecorderOptions options)
    : options_(std::move(options)),
      file_(std::make_unique<app::GzRawlogFile>(filePath(0), 1)),
      files_opened_(1),
      writer_(kMaxQueued, [this](Item& it) { write(it.first, it.second); })
{
}

Recorder::~Recorder()
{
    try
    {
        close();
    }
    catch (...)
    {
    }
}

std::string Recorder::filePath(size_t k) const
{
    return cut() ? app::numberedRawlogPath(options_.path, k) : options_.path;
}

void Recorder::startFrame(double t)
{
    if (cut()) enqueue(nullptr, t);
}

void Recorder::push(mrpt::obs::CObservation::Ptr o) { enqueue(std::move(o), 0); }

void Recorder::enqueue(mrpt::obs::CObservation::Ptr o, double frame_t)
{
    if (!writer_.push({std::move(o), frame_t})) writer_.rethrowError();
}

void Recorder::close()
{
    if (!closed_)
    {
        closed_ = true;
        writer_.close();
        if (!writer_.error())
        {
            try
            {
                file_->close();
                bytes_kept_ = closed_kept_bytes_ + file_->bytes();
            }
            catch (...)
            {
                close_error_ = std::current_exception();
            }
        }
    }
    writer_.rethrowError();
    if (close_error_) std::rethrow_exception(close_error_);
}

void Recorder::write(const mrpt::obs::CObservation::Ptr& o, double frame_t)
{
    if (!o)  // a frame starts: the file ends here if its time is up
    {
        if (!cut()) return;
        const auto stamp = [](const mrpt::obs::CObservation::Ptr& p) { return mrpt::Clock::toDouble(p->timestamp); };
        while (recent_poses_.size() > 1 && stamp(recent_poses_[1]) <= frame_t) recent_poses_.pop_front();
        // Frame times only grow: the capture drops a frame not after the one before.
        if (file_start_t_ < 0) file_start_t_ = frame_t;
        if (frame_t - file_start_t_ >= options_.part_seconds)
        {
            nextFile();
            file_start_t_ = frame_t;
            for (const auto& p : recent_poses_) file_->write(*p);
            bytes_kept_ = closed_kept_bytes_ + file_->bytes();
        }
        return;
    }
    file_->write(*o);
    bytes_kept_ = closed_kept_bytes_ + file_->bytes();
    if (dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(o.get()))
        ++frames_;
    else if (cut() && dynamic_cast<const mrpt::obs::CObservationRobotPose*>(o.get()))
        recent_poses_.push_back(o);
}

void Recorder::nextFile()
{
    file_->close();
    closed_sizes_.push_back(file_->bytes());
    closed_kept_bytes_ += file_->bytes();
    file_ = std::make_unique<app::GzRawlogFile>(filePath(files_opened_), 1);
    ++files_opened_;
    // The newest keep_files files stay (the one just opened among them).
    while (options_.keep_files > 0 && files_opened_ - files_deleted_ > options_.keep_files)
    {
        const std::string old = filePath(files_deleted_);
        std::error_code ec;
        std::filesystem::remove(old, ec);  // a file already gone is fine
        if (ec) throw io::WriteError(fmt::format("cannot delete the old recording '{}': {}", old, ec.message()));
        closed_kept_bytes_ -= closed_sizes_.front();
        closed_sizes_.pop_front();
        ++files_deleted_;
    }
    bytes_kept_ = closed_kept_bytes_;
}

}  // namespace pndt::live
