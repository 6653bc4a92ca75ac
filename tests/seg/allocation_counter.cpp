// The replaced global operator new / delete behind test::heapAllocations(). In a translation
// unit of its own: GCC flags malloc / free replacements it can see inlined into std::allocator.
// Not under sanitizers: they bring their own operator new (and report ours as mismatched).
#include "allocation_counter.h"

#include <atomic>
#include <cstdlib>
#include <new>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define PNDT_COUNT_ALLOCATIONS 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define PNDT_COUNT_ALLOCATIONS 0
#endif
#endif
#ifndef PNDT_COUNT_ALLOCATIONS
#define PNDT_COUNT_ALLOCATIONS 1
#endif

#if PNDT_COUNT_ALLOCATIONS
namespace
{
std::atomic<long> g_allocations{0};
}

long test::heapAllocations() { return g_allocations.load(std::memory_order_relaxed); }

void* operator new(std::size_t n)
{
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
#else
long test::heapAllocations() { return -1; }
#endif
