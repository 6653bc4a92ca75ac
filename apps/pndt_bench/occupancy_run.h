// An occupancy-only mapper's run over the bench's frames (OctoMap, Bonxai):
// each frame's time, for the same statistics as PanopticNDT's runs.
#pragma once

#include "bench_frames.h"

#include <chrono>
#include <cstddef>
#include <vector>

namespace pndt::bench
{
struct OccupancyRun
{
    double fps = 0;
    std::vector<double> frame_seconds;  ///< each frame's insert
    double finish_seconds = 0;          ///< work after the last frame (OctoMap's updateInnerOccupancy)
    size_t cells = 0;                   ///< leaves (OctoMap) or active cells (Bonxai)
    double bytes_per_cell = 0;
};

/// `insert(i)` for every frame, each timed; `finish()` after the last, timed
/// apart and counted in the frame rate.
template <class Insert, class Finish>
OccupancyRun timeFrames(const BenchFrames& b, Insert insert, Finish finish)
{
    using Clock = std::chrono::steady_clock;
    const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    OccupancyRun r;
    r.frame_seconds.resize(b.frames.size());
    const auto t0 = Clock::now();
    for (size_t i = 0; i < b.frames.size(); ++i)
    {
        const auto tf = Clock::now();
        insert(i);
        r.frame_seconds[i] = since(tf);
    }
    const auto t1 = Clock::now();
    finish();
    r.finish_seconds = since(t1);
    r.fps = double(b.frames.size()) / since(t0);
    return r;
}
}  // namespace pndt::bench
