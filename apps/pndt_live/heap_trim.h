// Hands the C library's freed heap pages back to the system. When the machine is busy,
// frames wait for the mapper (up to mapping_queue, ~3.5 MB each at 640x480); glibc keeps
// that memory in its arenas once they are mapped, so without this a robot's pndt-live would
// stay at its largest burst for the rest of a run of hours (doc/hardening.md, "Soak").
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace pndt::app
{
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
