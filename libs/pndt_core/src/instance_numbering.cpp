#include <pndt/instance_numbering.h>
#include <pndt/panoptic_map.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace pndt
{
InstanceNumbering::InstanceNumbering(std::vector<uint32_t> map_ids) : ids_(std::move(map_ids))
{
    std::sort(ids_.begin(), ids_.end());
    ids_.erase(std::unique(ids_.begin(), ids_.end()), ids_.end());
    if (!ids_.empty() && ids_.front() == 0) ids_.erase(ids_.begin());
    if (ids_.size() > kMaxDense)
        throw std::out_of_range("the map holds " + std::to_string(ids_.size()) +
                                " instances; a 16-bit instance field numbers at most 65535");
}

InstanceNumbering InstanceNumbering::of(const PanopticMap& map)
{
    std::vector<uint32_t> ids;
    for (const MapInstance& mi : map.instances()) ids.push_back(mi.id);
    return InstanceNumbering(std::move(ids));
}

uint32_t InstanceNumbering::dense(uint32_t map_id) const
{
    if (map_id == 0) return 0;
    const auto it = std::lower_bound(ids_.begin(), ids_.end(), map_id);
    if (it == ids_.end() || *it != map_id)
        throw std::out_of_range("instance id " + std::to_string(map_id) + " is not one of the map's " +
                                std::to_string(ids_.size()) + " instances");
    return uint32_t(it - ids_.begin()) + 1;
}

uint32_t InstanceNumbering::mapId(uint32_t dense) const
{
    if (dense == 0) return 0;
    if (dense > ids_.size())
        throw std::out_of_range("instance number " + std::to_string(dense) + " above the map's " +
                                std::to_string(ids_.size()) + " instances");
    return ids_[dense - 1];
}

bool InstanceNumbering::isIdentity() const { return ids_.empty() || ids_.back() == ids_.size(); }

}  // namespace pndt
