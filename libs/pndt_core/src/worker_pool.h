// A fixed set of worker threads for the map's parallel stages. The caller's
// thread takes part; run() returns when every task is done. Tasks are claimed
// dynamically, so a task must not depend on which thread runs it: every stage
// gives each task its own output and merges the outputs in a fixed order,
// which is what keeps the map identical for any thread count.
//
// A frame has about a dozen parallel stages with short serial parts between
// them, and waking a sleeping thread costs tens of microseconds or more (an
// idle virtual CPU is halted): during a frame (a Burst) idle workers, and the
// caller waiting for the last tasks of a stage, spin;
// between frames they spin for a short while (kSpin) and then sleep.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>
#ifdef __linux__
#include <pthread.h>
#include <sched.h>
#endif
#if defined(__x86_64__) || defined(_M_X64)
#include <immintrin.h>
#endif

namespace pndt
{
class WorkerPool
{
   public:
    /// `threads` in total, the caller included (1 = no workers). With `pin`,
    /// worker i runs on CPU i (modulo the CPU count): for benchmarks on
    /// machines whose scheduler packs threads onto few CPUs.
    explicit WorkerPool(int threads, bool pin = false)
        : spins_(std::thread::hardware_concurrency() == 0 || threads <= int(std::thread::hardware_concurrency()))
    {
        for (int i = 1; i < threads; ++i)
        {
            workers_.emplace_back([this, i] { workerLoop(i); });
            if (pin) pinToCpu(workers_.back(), i);
        }
    }
    ~WorkerPool()
    {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_.store(true);
        }
        wake_.notify_all();
        for (auto& t : workers_) t.join();
    }
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    /// Thread time since the pool started, for a frame's breakdown (the
    /// difference over the frame): the workers' time in tasks and background
    /// pieces, and the caller's time waiting for them. Complete once the
    /// stage that used them has returned (both are added before the worker
    /// lets go of the job or piece).
    std::chrono::nanoseconds workersBusy() const { return std::chrono::nanoseconds(workers_busy_ns_.load()); }
    std::chrono::nanoseconds callerWaiting() const { return std::chrono::nanoseconds(caller_waiting_ns_.load()); }

    int threads() const { return int(workers_.size()) + 1; }
    /// Whether idle threads spin between stages: only while there are no more threads than
    /// CPUs. With more, a spinning thread holds the CPU the thread it waits for needs (64
    /// threads on 2 CPUs mapped 10-13x slower than one); they then sleep at once and yield.
    bool spins() const { return spins_; }

    /// While a Burst lives (a frame's stages), idle workers spin instead of
    /// sleeping, up to kBurstSpin at a time. `pool` may be null.
    class Burst
    {
       public:
        explicit Burst(WorkerPool* pool) : pool_(pool)
        {
            if (pool_) pool_->bursts_.fetch_add(1);
        }
        ~Burst()
        {
            if (pool_) pool_->bursts_.fetch_sub(1);
        }
        Burst(const Burst&) = delete;
        Burst& operator=(const Burst&) = delete;

       private:
        WorkerPool* pool_;
    };

    /// Work for the workers while the caller goes on with other stages (the
    /// ray walk during matching and the histograms): a worker with no task calls
    /// piece(thread), which does one small piece and returns false when none
    /// is left; between pieces it takes the caller's run() tasks. finish()
    /// does the pieces left on the caller's thread (thread 0) and returns when
    /// no worker is inside one; the destructor finishes too (an exception
    /// thrown by the caller's stage must not leave workers in a dead frame).
    /// Pieces must not depend on which thread runs them. One at a time.
    class Background
    {
       public:
        template <typename Fn>
        Background(WorkerPool* pool, Fn& piece) : pool_(pool), ctx_(&piece)
        {
            call_ = [](void* ctx, int thread) { return (*static_cast<Fn*>(ctx))(thread); };
            if (pool_ && !pool_->workers_.empty()) pool_->post(this);
        }
        ~Background()
        {
            try
            {
                finish();
            }
            catch (...)  // the caller's own exception is on its way already
            {
            }
        }
        Background(const Background&) = delete;
        Background& operator=(const Background&) = delete;

        void finish()
        {
            if (finished_) return;
            finished_ = true;
            std::exception_ptr mine;
            try
            {
                while (call_(ctx_, 0))
                {
                }
            }
            catch (...)  // rethrown once no worker is inside a piece
            {
                mine = std::current_exception();
            }
            if (pool_ && !pool_->workers_.empty()) pool_->withdraw();
            if (mine) std::rethrow_exception(mine);
            if (error_) std::rethrow_exception(error_);
        }

       private:
        friend class WorkerPool;
        WorkerPool* pool_;
        void* ctx_;
        bool (*call_)(void*, int) = nullptr;
        uint64_t seq_ = 0;
        bool finished_ = false;
        std::exception_ptr error_;  // under the pool's mutex_
    };

    /// Calls fn(task) for every task in [0, n); `fn` may run on any thread.
    /// Exceptions are caught and the first is rethrown here.
    template <typename Fn>
    void run(int n, Fn&& fn)
    {
        runWithThread(n, [&fn](int task, int) { fn(task); });
    }
    /// Calls fn(task, thread) for every task in [0, n); `thread` in
    /// [0, threads()) names the thread running it (for per-thread scratch).
    template <typename Fn>
    void runWithThread(int n, Fn&& fn)
    {
        if (n <= 0) return;
        if (workers_.empty() || n == 1)
        {
            for (int i = 0; i < n; ++i) fn(i, 0);
            return;
        }
        Job job;
        using F = std::remove_reference_t<Fn>;
        job.ctx = const_cast<void*>(static_cast<const void*>(&fn));
        job.call = [](void* ctx, int task, int thread) { (*static_cast<F*>(ctx))(task, thread); };
        job.tasks = n;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            job_.store(&job);
            generation_.fetch_add(1);
        }
        wake_.notify_all();
        work(job, 0);
        // Wait for the tasks other threads took: spin a little (during a burst
        // as long as the workers do: the next stage follows), then sleep.
        const auto waiting = std::chrono::steady_clock::now();
        const auto until = waiting + (!spins_ ? std::chrono::microseconds(0) : bursts_.load() > 0 ? kBurstSpin : kSpin);
        while (job.finished.load() < job.tasks && std::chrono::steady_clock::now() < until) pause();
        if (job.finished.load() < job.tasks)
        {
            std::unique_lock<std::mutex> lock(mutex_);
            done_.wait(lock, [&] { return job.finished.load() >= job.tasks; });
        }
        // No worker may still hold the job when it goes out of scope.
        job_.store(nullptr);
        while (busy_.load() != 0) relax();
        addSince(caller_waiting_ns_, waiting);
        if (job.error) std::rethrow_exception(job.error);
    }

   private:
    static constexpr std::chrono::microseconds kSpin{50};
    /// Longest spin during a burst: serial parts of a frame are shorter; a
    /// long one (a caller between stages) ends in sleep.
    static constexpr std::chrono::microseconds kBurstSpin{20000};

    struct Job
    {
        void* ctx = nullptr;
        void (*call)(void*, int, int) = nullptr;
        int tasks = 0;
        std::atomic<int> next{0};
        std::atomic<int> finished{0};
        std::exception_ptr error;  // under mutex_
    };

    void post(Background* bg)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        bg->seq_ = background_seq_.load() + 1;
        background_.store(bg);
        background_seq_.store(bg->seq_);
        generation_.fetch_add(1);  // wakes sleeping workers; no job: they go to the pieces
        wake_.notify_all();
    }
    void withdraw()
    {
        background_.store(nullptr);
        const auto waiting = std::chrono::steady_clock::now();
        while (background_busy_.load() != 0) relax();
        addSince(caller_waiting_ns_, waiting);
    }
    /// A worker's piece of the background work; false when there was none
    /// (`exhausted` then remembers the work, so the worker stops asking).
    bool backgroundPiece(int thread, uint64_t& exhausted)
    {
        const uint64_t seq = background_seq_.load();
        if (seq == exhausted) return false;
        // Announce before looking at it, so that withdraw() cannot return (and
        // the work disappear) between the two.
        background_busy_.fetch_add(1);
        bool more = false;
        if (Background* bg = background_.load())
        {
            const auto start = std::chrono::steady_clock::now();
            try
            {
                more = bg->call_(bg->ctx_, thread);
            }
            catch (...)
            {
                std::lock_guard<std::mutex> lock(mutex_);
                if (!bg->error_) bg->error_ = std::current_exception();
            }
            addSince(workers_busy_ns_, start);
            if (!more) exhausted = bg->seq_;
        }
        else
            exhausted = seq;
        background_busy_.fetch_sub(1);
        return more;
    }

    static void addSince(std::atomic<int64_t>& total, std::chrono::steady_clock::time_point start)
    {
        total.fetch_add(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start)
                            .count(),
                        std::memory_order_relaxed);
    }

    /// Waiting for another thread to let go: a pause while it has a CPU of its own, else a
    /// yield so that it gets one.
    void relax() const
    {
        if (spins_)
            pause();
        else
            std::this_thread::yield();
    }

    static void pause()
    {
#if defined(__x86_64__) || defined(_M_X64)
        _mm_pause();
#else
        std::this_thread::yield();
#endif
    }

    void work(Job& job, int thread)
    {
        int done = 0;
        for (int t; (t = job.next.fetch_add(1)) < job.tasks; ++done)
        {
            try
            {
                job.call(job.ctx, t, thread);
            }
            catch (...)
            {
                std::lock_guard<std::mutex> lock(mutex_);
                if (!job.error) job.error = std::current_exception();
            }
        }
        if (done > 0 && job.finished.fetch_add(done) + done >= job.tasks)
        {
            std::lock_guard<std::mutex> lock(mutex_);  // the caller may be about to sleep
            done_.notify_all();
        }
    }

    static void pinToCpu(std::thread& t, int i)
    {
#ifdef __linux__
        const int n = int(std::thread::hardware_concurrency());
        if (n <= 1) return;
        cpu_set_t set;
        CPU_ZERO(&set);
        CPU_SET(i % n, &set);
        pthread_setaffinity_np(t.native_handle(), sizeof(set), &set);
#else
        (void)t;
        (void)i;
#endif
    }

    void workerLoop(int thread)
    {
        uint64_t seen = 0, exhausted = 0;
        for (;;)
        {
            // A new job: spin (a little, or during a burst), then sleep until one comes.
            auto start = std::chrono::steady_clock::now();
            for (;;)
            {
                if (generation_.load() != seen || stop_.load()) break;
                if (backgroundPiece(thread, exhausted))
                {
                    start = std::chrono::steady_clock::now();
                    continue;
                }
                const auto spun = std::chrono::steady_clock::now() - start;
                if (!spins_ || spun >= kBurstSpin || (spun >= kSpin && bursts_.load() == 0)) break;
                pause();
            }
            if (generation_.load() == seen && !stop_.load())
            {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait(lock, [&] { return stop_.load() || generation_.load() != seen; });
            }
            if (stop_.load()) return;
            seen = generation_.load();
            // Announce before looking at the job, so that run() cannot return
            // (and the job disappear) between the two.
            busy_.fetch_add(1);
            if (Job* job = job_.load())
            {
                const auto start = std::chrono::steady_clock::now();
                work(*job, thread);
                addSince(workers_busy_ns_, start);
            }
            busy_.fetch_sub(1);
        }
    }

    const bool spins_;  ///< before workers_: set before the first worker starts
    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::atomic<Job*> job_{nullptr};
    std::atomic<uint64_t> generation_{0};
    std::atomic<int> busy_{0};
    std::atomic<int64_t> workers_busy_ns_{0}, caller_waiting_ns_{0};
    std::atomic<int> bursts_{0};
    std::atomic<bool> stop_{false};
    std::atomic<Background*> background_{nullptr};
    std::atomic<uint64_t> background_seq_{0};
    std::atomic<int> background_busy_{0};
};

}  // namespace pndt
