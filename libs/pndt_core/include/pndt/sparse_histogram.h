// Fixed-capacity histogram kept sorted by weight (largest first); when full, a
// new id replaces the smallest entry (design §2). Id 0 (void, no instance) is
// never stored: it marks the free entries, which follow the used ones. Count
// and sum are derived from the entries, not stored: they cost 8 bytes per
// histogram, and histograms are most of a map's memory.
#pragma once

#include <cstdint>
#include <utility>

namespace pndt
{
template <typename Id, int Capacity>
struct SparseHistogram
{
    static constexpr int kCapacity = Capacity;

    Id ids[Capacity]{};
    float weights[Capacity]{};

    /// Entries in use.
    int size() const
    {
        int n = 0;
        while (n < Capacity && ids[n] != 0) ++n;
        return n;
    }
    /// Sum of the stored weights, strongest first.
    float sum() const
    {
        float s = 0;
        for (int i = 0; i < Capacity && ids[i] != 0; ++i) s += weights[i];
        return s;
    }
    /// Adds `w` to `id` (not 0). When full, the smallest entry is evicted: its
    /// id is returned (0 otherwise) and its weight stored in `evicted_weight`.
    Id add(Id id, float w, float* evicted_weight = nullptr)
    {
        int i = indexOf(id);
        Id evicted = 0;
        if (i >= 0)
            weights[i] += w;
        else if (const int n = size(); n < Capacity)
        {
            i = n;
            ids[i] = id;
            weights[i] = w;
        }
        else
        {
            i = Capacity - 1;
            evicted = ids[i];
            if (evicted_weight) *evicted_weight = weights[i];
            ids[i] = id;
            weights[i] = w;
        }
        // Restore descending order; ties keep the older entry first.
        while (i > 0 && weights[i] > weights[i - 1])
        {
            std::swap(weights[i], weights[i - 1]);
            std::swap(ids[i], ids[i - 1]);
            --i;
        }
        return evicted;
    }
    /// Index of `id` (not 0), or -1.
    int indexOf(Id id) const
    {
        for (int i = 0; i < Capacity && ids[i] != 0; ++i)
            if (ids[i] == id) return i;
        return -1;
    }
    float weightOf(Id id) const
    {
        const int i = indexOf(id);
        return i < 0 ? 0.f : weights[i];
    }
    bool empty() const { return ids[0] == 0; }
    Id top() const { return ids[0]; }
    void clear() { *this = SparseHistogram{}; }
};

}  // namespace pndt
