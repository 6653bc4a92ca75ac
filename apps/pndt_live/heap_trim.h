// Hands the C library's freed heap pages back to the system. When the machine is busy,
// frames wait for the mapper (up to mapping_queue, ~3.5 MB each at 640x480); glibc keeps
// that memory in its arenas once they are mapped, so without this a robot's pndt-live would
// stay at its largest burst for the rest of a run of hours (doc/hardening.md, "Soak").
// And one glibc arena for the process (capHeapArenas).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace pndt::app
{
/// One glibc arena for the whole process, unless $MALLOC_ARENA_MAX says otherwise. With one
/// arena per thread (frames allocated on one thread, freed on another) RSS crept 20-35 MB an
/// hour while the heap in use stayed flat; with one arena its lows stayed flat for 80 minutes
/// (doc/hardening.md, "Soak"). pndt-live's threads allocate a few large buffers a frame (the
/// map's hot path none), so the one lock should cost little (not measured). Call before any
/// thread starts; returns the cap set (0: none set).
inline int capHeapArenas()
{
#ifdef __GLIBC__
    if (std::getenv("MALLOC_ARENA_MAX")) return 0;
    if (mallopt(M_ARENA_MAX, 1) == 1) return 1;
#endif
    return 0;
}

struct HeapTrim
{
    uint64_t runs = 0;
    double longest_ms = 0;

    void run()
    {
#ifdef __GLIBC__
        const auto t0 = std::chrono::steady_clock::now();
        malloc_trim(0);
        longest_ms = std::max(longest_ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        ++runs;
#endif
    }
};
}  // namespace pndt::app
