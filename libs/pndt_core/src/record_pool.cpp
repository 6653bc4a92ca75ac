#include <pndt/record_pool.h>

#include <sys/mman.h>
#include <unistd.h>

#include <new>

namespace pndt::pool_pages
{
size_t roundUp(size_t bytes) noexcept
{
    static const size_t page = size_t(sysconf(_SC_PAGESIZE));
    return (bytes + page - 1) / page * page;
}

void* map(size_t bytes)
{
    void* p = mmap(nullptr, roundUp(bytes), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    return p;
}

void* grow(void* p, size_t old_bytes, size_t new_bytes)
{
    void* q = mremap(p, roundUp(old_bytes), roundUp(new_bytes), MREMAP_MAYMOVE);
    if (q == MAP_FAILED) throw std::bad_alloc();
    return q;
}

void unmap(void* p, size_t bytes) noexcept { munmap(p, roundUp(bytes)); }

}  // namespace pndt::pool_pages
