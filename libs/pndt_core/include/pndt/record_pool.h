// A growable array of trivially copyable records in an anonymous memory
// mapping of its own. It grows by remapping (mremap), not by copying: records
// already written are neither copied nor touched again, and the room ahead is
// address space only, backed by memory on first write. A std::vector pool that
// grows by a quarter copies and first-touches ~5x its final size over a map's
// life, on the mapping thread; this one touches every page once.
//
// The map's voxel, locator, slot and record arrays live in these pools; what
// they cost is what they use (bytesUsed: the pages their records cover).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <initializer_list>
#include <iterator>
#include <new>
#include <type_traits>
#include <utility>

namespace pndt
{
namespace pool_pages
{
// Sizes are rounded up to whole pages.
/// Anonymous read-write mapping of `bytes` (> 0). Throws std::bad_alloc.
void* map(size_t bytes);
/// Grows a mapping from `old_bytes` to `new_bytes`, moving it if it must
/// (pages are moved, not copied). Throws std::bad_alloc; `p` stays valid then.
void* grow(void* p, size_t old_bytes, size_t new_bytes);
void unmap(void* p, size_t bytes) noexcept;
/// `bytes` rounded up to whole pages.
size_t roundUp(size_t bytes) noexcept;
}  // namespace pool_pages

template <typename T>
class RecordPool
{
    static_assert(std::is_trivially_copyable_v<T>, "records are moved by remapping their pages");

   public:
    using value_type = T;
    using iterator = T*;
    using const_iterator = const T*;

    RecordPool() = default;
    RecordPool(std::initializer_list<T> init) { assign(init.begin(), init.end()); }
    RecordPool(const RecordPool& o) { assign(o.begin(), o.end()); }
    RecordPool(RecordPool&& o) noexcept { swap(o); }
    RecordPool& operator=(const RecordPool& o)
    {
        if (this != &o) assign(o.begin(), o.end());
        return *this;
    }
    RecordPool& operator=(RecordPool&& o) noexcept
    {
        RecordPool(std::move(o)).swap(*this);
        return *this;
    }
    ~RecordPool() { release(); }
    void swap(RecordPool& o) noexcept
    {
        std::swap(data_, o.data_);
        std::swap(size_, o.size_);
        std::swap(capacity_, o.capacity_);
    }

    size_t size() const { return size_; }
    size_t capacity() const { return capacity_; }
    bool empty() const { return size_ == 0; }
    T* data() { return data_; }
    const T* data() const { return data_; }
    T& operator[](size_t i) { return data_[i]; }
    const T& operator[](size_t i) const { return data_[i]; }
    T& back() { return data_[size_ - 1]; }
    const T& back() const { return data_[size_ - 1]; }
    T* begin() { return data_; }
    T* end() { return data_ + size_; }
    const T* begin() const { return data_; }
    const T* end() const { return data_ + size_; }

    /// Bytes of the pages the records cover (what the pool costs in memory).
    size_t bytesUsed() const { return size_ ? pool_pages::roundUp(size_ * sizeof(T)) : 0; }

    void reserve(size_t n)
    {
        if (n <= capacity_) return;
        // Doubling costs address space only; 64 KB at least, so that small
        // pools do not remap for every few records.
        const size_t want = std::max({n, 2 * capacity_, size_t(65536) / sizeof(T) + 1});
        const size_t bytes = pool_pages::roundUp(want * sizeof(T));
        data_ = static_cast<T*>(data_ ? pool_pages::grow(data_, capacity_ * sizeof(T), bytes) : pool_pages::map(bytes));
        capacity_ = bytes / sizeof(T);
    }
    T& emplace_back()
    {
        if (size_ == capacity_) reserve(size_ + 1);
        return *new (data_ + size_++) T();
    }
    void push_back(const T& v)
    {
        if (size_ == capacity_) reserve(size_ + 1);
        data_[size_++] = v;
    }
    /// Appends `k` records for the caller to write (from several threads, say:
    /// the first write to a new page is then not all on one thread); returns
    /// the first of them.
    T* appendUnwritten(size_t k)
    {
        reserve(size_ + k);
        T* first = data_ + size_;
        size_ += k;
        return first;
    }
    /// Grows with copies of `v` or shrinks (pages stay mapped).
    void resize(size_t n, const T& v = T())
    {
        reserve(n);
        for (size_t i = size_; i < n; ++i) data_[i] = v;
        size_ = n;
    }
    template <typename It>
    void assign(It first, It last)
    {
        clear();
        const size_t n = size_t(std::distance(first, last));
        if (n == 0) return;
        reserve(n);
        std::copy(first, last, data_);
        size_ = n;
    }
    /// Empties the pool and gives its memory back.
    void clear() noexcept { release(); }

   private:
    void release() noexcept
    {
        if (data_) pool_pages::unmap(data_, capacity_ * sizeof(T));
        data_ = nullptr;
        size_ = capacity_ = 0;
    }

    T* data_ = nullptr;
    size_t size_ = 0;
    size_t capacity_ = 0;  ///< records the mapping holds (a whole number of pages)
};

}  // namespace pndt
