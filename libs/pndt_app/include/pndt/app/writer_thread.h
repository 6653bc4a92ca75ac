// A thread that writes queued items in order, for the rawlog writers (maps.rawlog,
// pndt-live's recording): the caller only queues, the slow part (serialising,
// compressing, the disk) runs here. The queue is bounded: push() waits while it is full,
// so a disk slower than the producer holds the producer back instead of growing memory.
// The first error thrown by `write` stops the writing: it is kept for the owner to
// rethrow, and what is still queued is drained unwritten (the file ends where the error
// was).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

namespace pndt::app
{
template <class Item>
class WriterThread
{
   public:
    /// Starts the thread; `write` runs on it, one item at a time, in queue order.
    WriterThread(size_t max_queued, std::function<void(Item&)> write)
        : max_queued_(max_queued), write_(std::move(write)), thread_([this] { run(); })
    {
    }
    /// Writes what is queued and stops (errors stay unreported: the owner calls close()).
    ~WriterThread() { close(); }
    WriterThread(const WriterThread&) = delete;
    WriterThread& operator=(const WriterThread&) = delete;

    /// Queues `item`, waiting while the queue is full. False (the item dropped) once an
    /// error stopped the writing.
    bool push(Item item)
    {
        std::unique_lock<std::mutex> lock(mutex_);
        cv_.wait(lock, [&] { return queue_.size() < max_queued_ || error_; });
        if (error_) return false;
        queue_.push_back(std::move(item));
        cv_.notify_all();
        return true;
    }
    /// Waits until everything queued is written (or drained after an error) and stops the
    /// thread. Idempotent; no push() after it.
    void close()
    {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            closing_ = true;
        }
        cv_.notify_all();
        if (thread_.joinable()) thread_.join();
    }
    /// The first error `write` threw (null if none).
    std::exception_ptr error() const
    {
        std::lock_guard<std::mutex> lock(mutex_);
        return error_;
    }
    void rethrowError() const
    {
        if (const auto e = error()) std::rethrow_exception(e);
    }
    /// Seconds spent in `write`.
    double secondsWriting() const
    {
        std::lock_guard<std::mutex> lock(mutex_);
        return seconds_;
    }

   private:
    void run()
    {
        for (;;)
        {
            std::unique_lock<std::mutex> lock(mutex_);
            cv_.wait(lock, [&] { return closing_ || !queue_.empty(); });
            if (queue_.empty()) return;  // closing and drained
            Item item = std::move(queue_.front());
            queue_.pop_front();
            const bool failed = bool(error_);
            lock.unlock();
            cv_.notify_all();  // room in the queue
            if (failed) continue;
            const auto t0 = std::chrono::steady_clock::now();
            std::exception_ptr e;
            try
            {
                write_(item);
            }
            catch (...)
            {
                e = std::current_exception();
            }
            const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            lock.lock();
            seconds_ += dt;
            if (e && !error_) error_ = e;
            lock.unlock();
            if (e) cv_.notify_all();  // producers waiting for room give up
        }
    }

    const size_t max_queued_;
    const std::function<void(Item&)> write_;
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Item> queue_;
    bool closing_ = false;
    std::exception_ptr error_;
    double seconds_ = 0;
    std::thread thread_;  ///< last: started once everything above is in place
};

}  // namespace pndt::app
