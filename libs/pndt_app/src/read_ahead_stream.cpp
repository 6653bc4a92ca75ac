#include <pndt/app/read_ahead_stream.h>

namespace pndt::app
{
ReadAheadStream::ReadAheadStream(const std::string& path, size_t depth)
    : ReadAheadStream(std::vector<std::string>{path}, depth)
{
}

ReadAheadStream::ReadAheadStream(std::vector<std::string> paths, size_t depth)
    : in_(std::move(paths)), depth_(std::max<size_t>(1, depth)), reader_([this] { readLoop(); })
{
}

ReadAheadStream::~ReadAheadStream()
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
        changed_.notify_all();
    }
    reader_.join();
}

void ReadAheadStream::readLoop()
{
    for (;;)
    {
        mrpt::obs::CObservation::Ptr obs;
        std::exception_ptr error;
        try
        {
            obs = in_.next();
        }
        catch (...)
        {
            error = std::current_exception();
        }
        const double read_to = in_.progress();
        std::unique_lock<std::mutex> lock(mutex_);
        if (!obs || error)
        {
            error_ = error;
            ended_ = true;
            changed_.notify_all();
            return;
        }
        changed_.wait(lock, [&] { return stop_ || queue_.size() < depth_; });
        if (stop_) return;
        queue_.emplace_back(std::move(obs), read_to);
        changed_.notify_all();
    }
}

mrpt::obs::CObservation::Ptr ReadAheadStream::next()
{
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return !queue_.empty() || ended_; });
    if (!queue_.empty())
    {
        auto obs = std::move(queue_.front().first);
        progress_ = queue_.front().second;
        queue_.pop_front();
        changed_.notify_all();
        return obs;
    }
    progress_ = 1.0;
    if (error_) std::rethrow_exception(error_);
    return nullptr;
}

bool ReadAheadStream::truncated() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return ended_ && in_.truncated();
}

const std::string& ReadAheadStream::stopReason() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    static const std::string kNone;
    return ended_ ? in_.stopReason() : kNone;
}

double ReadAheadStream::progress() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return progress_;
}

}  // namespace pndt::app
