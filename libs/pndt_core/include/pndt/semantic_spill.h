// The classes a voxel's h^L holds beyond its record's 8 entries when eviction is
// off (MapOptions::semantic_eviction = false: the paper's dense histogram over the
// class set). Kept per map, keyed by label record, and empty unless a voxel saw
// more than 8 classes, so the default path never looks here.
//
// Invariant: every spilled weight is at most every weight in the record. The
// record thus holds the histogram's strongest classes (argmax reads the record
// alone); sums and per-class masses read both (instance_rules.h).
#pragma once

#include <pndt/voxel.h>
#include <tsl/robin_map.h>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace pndt
{
struct SemanticSpill
{
    struct Entry
    {
        uint8_t cls = 0;
        float weight = 0;
    };
    std::vector<Entry> entries;

    float sum() const
    {
        float s = 0;
        for (const Entry& e : entries) s += e.weight;
        return s;
    }
};

class SemanticSpills
{
   public:
    bool empty() const { return map_.empty(); }
    size_t size() const { return map_.size(); }
    /// The spill of a label record, or nullptr (also for kNoRecord).
    const SemanticSpill* find(uint32_t label_record) const
    {
        if (map_.empty()) return nullptr;
        const auto it = map_.find(label_record);
        return it == map_.end() ? nullptr : &it->second;
    }
    /// Adds `score` to class `cls` of the histogram made of `rec` (record
    /// `label_record`) and its spill: in the record if it holds the class;
    /// otherwise the class's spilled weight grows, and takes the record's
    /// smallest entry's place (which spills) once it is larger.
    void add(uint32_t label_record, LabelRecord& rec, uint8_t cls, float score);
    void erase(uint32_t label_record) { map_.erase(label_record); }
    void clear() { map_.clear(); }
    /// Replaces a record's spill (restoring a map); an empty one erases it.
    void set(uint32_t label_record, SemanticSpill spill);
    /// Every spill, by label record (for serialisation).
    std::vector<std::pair<uint32_t, const SemanticSpill*>> sorted() const;
    size_t memoryBytes() const;

   private:
    tsl::robin_map<uint32_t, SemanticSpill> map_;
};

}  // namespace pndt
