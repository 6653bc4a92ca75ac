// Fixed-capacity histogram kept sorted by weight (largest first); when full, a
// new id replaces the smallest entry (design §2). Id 0 (void, no instance) is
// never stored: it marks the free entries, which follow the used ones. Count
// and sum are derived from the entries, not stored: they cost 8 bytes per
// histogram, and histograms are most of a map's memory. How the weights are
// stored (floats, or 16-bit with a shared scale) is the Weights parameter
// (histogram_weights.h).
#pragma once

#include <pndt/histogram_weights.h>

#include <cstdint>
#include <utility>

namespace pndt
{
template <typename Id, int Capacity, typename Weights = FloatWeights<Capacity>>
struct SparseHistogram
{
    static constexpr int kCapacity = Capacity;

    Id ids[Capacity]{};
    Weights weights;

    /// Weight of entry i (i < size()).
    float weight(int i) const { return weights.get(i); }
    /// Sets entry i's weight; the caller restores the order (bubbleUp).
    void setWeight(int i, float w) { weights.set(i, w); }

    /// Entries in use.
    int size() const
    {
        int n = 0;
        while (n < Capacity && ids[n] != 0) ++n;
        return n;
    }
    /// Sum of the stored weights, strongest first.
    float sum() const { return weights.sum(size()); }
    /// Adds `w` to `id` (not 0). When full, the smallest entry is evicted: its
    /// id is returned (0 otherwise) and its weight stored in `evicted_weight`.
    Id add(Id id, float w, float* evicted_weight = nullptr)
    {
        int i = indexOf(id);
        Id evicted = 0;
        if (i >= 0)
            weights.set(i, weights.get(i) + w);
        else if (const int n = size(); n < Capacity)
        {
            i = n;
            ids[i] = id;
            weights.set(i, w);
        }
        else
        {
            i = Capacity - 1;
            evicted = ids[i];
            if (evicted_weight) *evicted_weight = weights.get(i);
            ids[i] = id;
            weights.set(i, w);
        }
        bubbleUp(i);
        return evicted;
    }
    /// Restores descending order after entry i grew; ties keep the older
    /// entry first.
    void bubbleUp(int i)
    {
        while (i > 0 && weights.greater(i, i - 1))
        {
            weights.swapEntries(i, i - 1);
            std::swap(ids[i], ids[i - 1]);
            --i;
        }
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
        return i < 0 ? 0.f : weights.get(i);
    }
    bool empty() const { return ids[0] == 0; }
    Id top() const { return ids[0]; }
    void clear() { *this = SparseHistogram{}; }
};

}  // namespace pndt
