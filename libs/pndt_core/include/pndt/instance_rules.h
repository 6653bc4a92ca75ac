// The per-voxel predicates of the paper's Eq. 2-10 (arXiv v2), free of any map.
#pragma once

#include <pndt/class_set.h>
#include <pndt/semantic_spill.h>
#include <pndt/voxel.h>

#include <cmath>

namespace pndt
{
// `spill`: the classes h^L holds beyond the record (semantic_eviction = false),
// nullptr when there are none. The record always holds the strongest classes.

/// The stuff part of h^L: the weight of its stuff classes.
inline float stuffMass(const LabelRecord& r, const ClassSet& classes, const SemanticSpill* spill = nullptr)
{
    float stuff = 0;
    for (int j = 0, n = r.semantic.size(); j < n; ++j)
        if (!classes.isThing(r.semantic.ids[j])) stuff += r.semantic.weight(j);
    if (spill)
        for (const auto& e : spill->entries)
            if (!classes.isThing(e.cls)) stuff += e.weight;
    return stuff;
}

/// The mass of h^L.
inline float semanticMass(const LabelRecord& r, const SemanticSpill* spill = nullptr)
{
    return spill ? r.semantic.sum() + spill->sum() : r.semantic.sum();
}

/// argmax h^L as a class id (the void bin reads as void, 0); 0 without evidence.
inline uint16_t semanticArgmax(const LabelRecord& r)
{
    const uint8_t top = r.semantic.top();
    return top == kVoidBin ? 0 : top;
}

/// isthing(v): the stuff share of h^L is below theta_st. A voxel without
/// semantic mass is not a thing. Both masses are summed in double: float sums
/// round, and a share of exactly theta_st came out just below it (a thing).
inline bool isThing(const LabelRecord& r, const ClassSet& classes, double theta_st,
                    const SemanticSpill* spill = nullptr)
{
    double sum = 0, stuff = 0;
    for (int j = 0, n = r.semantic.size(); j < n; ++j)
    {
        const double w = r.semantic.weight(j);
        sum += w;
        if (!classes.isThing(r.semantic.ids[j])) stuff += w;
    }
    if (spill)
        for (const auto& e : spill->entries)
        {
            sum += e.weight;
            if (!classes.isThing(e.cls)) stuff += e.weight;
        }
    return sum > 0 && stuff / sum < theta_st;
}

/// isintopz(v, z): z belongs to the highest-weight entries that together hold at
/// least theta_b of the mass, i.e. the ascending cumulative sum up to and
/// including z's weight (all entries weighing <= w(z)) is >= (1 - theta_b) of it.
/// The total is summed in double as the cumulative sum is: against the float
/// sum, an entry holding exactly 1 - theta_b fell out when that sum rounded up.
inline bool isInTopZ(const InstanceHistogram& h, uint32_t z, double theta_b)
{
    const int i = h.indexOf(z);
    if (i < 0) return false;
    const float wz = h.weight(i);
    double cum = 0, total = 0;
    for (int j = 0, n = h.size(); j < n; ++j)
    {
        const float w = h.weight(j);
        total += w;
        if (w <= wz) cum += w;
    }
    return total > 0 && cum >= (1.0 - theta_b) * total;
}

/// pthing(v): a thing voxel that saw instances often enough relative to its
/// semantic observations (n^Z / n^L >= theta_o).
inline bool isPanopticThing(const LabelRecord& r, const InstanceRecord& z, const ClassSet& classes, double theta_st,
                            double theta_o, const SemanticSpill* spill = nullptr)
{
    return isThing(r, classes, theta_st, spill) && r.n_l > 0 && double(z.n_z) >= theta_o * double(r.n_l);
}

/// Adds a voxel's thing-class mass of h^L to per-class sums (an instance's class
/// is the argmax of these sums over its voxels).
template <typename T>
inline void addThingMass(const LabelRecord& r, const ClassSet& classes, T* per_class,
                         const SemanticSpill* spill = nullptr)
{
    for (int j = 0, n = r.semantic.size(); j < n; ++j)
        if (classes.isThing(r.semantic.ids[j])) per_class[r.semantic.ids[j]] += r.semantic.weight(j);
    if (spill)
        for (const auto& e : spill->entries)
            if (classes.isThing(e.cls)) per_class[e.cls] += e.weight;
}

/// The thing class with the most mass in a voxel's own h^L, or 0 if it has none.
inline uint16_t ownThingClass(const LabelRecord& r, const ClassSet& classes, const SemanticSpill* spill = nullptr)
{
    float best = 0;
    uint16_t c = 0;
    for (int j = 0, n = r.semantic.size(); j < n; ++j)
        if (classes.isThing(r.semantic.ids[j]) && r.semantic.weight(j) > best)
        {
            best = r.semantic.weight(j);
            c = r.semantic.ids[j];
        }
    // Spilled weights are at most the record's: only needed when it has no thing class.
    if (c == 0 && spill)
        for (const auto& e : spill->entries)
            if (classes.isThing(e.cls) && e.weight > best)
            {
                best = e.weight;
                c = e.cls;
            }
    return c;
}

/// A map instance's score for AP and queries: the share of h^Z weight its voxels
/// give it (rival ids on the same voxels lower it) times a saturating count of
/// the frames that saw it (1 frame 0.28, 3 frames 0.63, 10 frames 0.96): an
/// object seen once, or contested, ranks below one seen often and alone.
inline double instanceConfidence(double weight_share, uint32_t frames_seen)
{
    constexpr double kFramesScale = 3.0;
    return weight_share * (1.0 - std::exp(-double(frames_seen) / kFramesScale));
}

/// Outcome of matching one predicted instance against the map's instances.
enum class MatchKind
{
    Matched,    ///< best IoU > theta_m: take that map instance
    New,        ///< best IoU <= theta_n: a new, globally unique id
    Ambiguous,  ///< in between: instance 0, no instance update
};

inline MatchKind classifyMatch(double best_iou, double theta_m, double theta_n)
{
    if (best_iou > theta_m) return MatchKind::Matched;
    if (best_iou <= theta_n) return MatchKind::New;
    return MatchKind::Ambiguous;
}

inline double intersectionOverUnion(uint64_t intersection, uint64_t area_a, uint64_t area_b)
{
    const uint64_t uni = area_a + area_b - intersection;
    return uni == 0 ? 0.0 : double(intersection) / double(uni);
}

}  // namespace pndt
