// A dense numbering of one map's instances, for encodings with a 16-bit instance field
// (the published sem << 16 | ins label, the PLY `label`, label PNGs).
//
// Map instance ids are unique across short-term maps: each map draws its new ids from its
// own block of 65536 (app/short_term_maps.h), so after the first hand-over ids exceed 65535.
// Cutting them to 16 bits would merge instances; the numbering instead gives the instances a
// map holds, in ascending order of their map id, the numbers 1..N (0 stays 0: stuff, none).
// It is deterministic (same map, same numbers) and invertible (mapId()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pndt
{
class PanopticMap;

class InstanceNumbering
{
   public:
    /// Largest number the 16-bit encodings hold.
    static constexpr uint32_t kMaxDense = 65535;

    InstanceNumbering() = default;
    /// From map ids in any order (duplicates and 0 ignored). Throws std::out_of_range when
    /// there are more than kMaxDense of them (saying how many).
    explicit InstanceNumbering(std::vector<uint32_t> map_ids);
    /// The instances of `map` after propagation (PanopticMap::instances()).
    static InstanceNumbering of(const PanopticMap& map);

    /// 1..size() for a known id, 0 for 0. Throws std::out_of_range naming an unknown id.
    uint32_t dense(uint32_t map_id) const;
    /// The map id numbered `dense` (0 for 0). Throws std::out_of_range for a number > size().
    uint32_t mapId(uint32_t dense) const;
    /// True when every id equals its number's map id (e.g. the first short-term map's ids
    /// 1..N without gaps): encodings then carry the map's own ids.
    bool isIdentity() const;
    size_t size() const { return ids_.size(); }

   private:
    std::vector<uint32_t> ids_;  // sorted map ids; number k+1 is ids_[k]
};

}  // namespace pndt
