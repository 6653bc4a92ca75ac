#include <pndt/voxel_store.h>

#include <fmt/format.h>

#include <stdexcept>

namespace pndt
{
uint32_t VoxelStore::brickFor(uint64_t brick_key)
{
    const auto it = brick_index_.find(brick_key);
    if (it != brick_index_.end()) return it->second;
    if (brick_origin_.size() >= kMaxBricks)
        throw std::length_error(fmt::format("voxel store: more than {} bricks", kMaxBricks));
    const uint32_t b = uint32_t(brick_origin_.size());
    brick_index_.emplace(brick_key, b);
    const VoxelKey bk = VoxelKey::unpack(brick_key);
    brick_origin_.push_back({bk.x * kBrickEdge, bk.y * kBrickEdge, bk.z * kBrickEdge});
    slots_.resize(slots_.size() + kBrickSlots, kNoRecord);
    return b;
}

uint32_t VoxelStore::create(uint32_t brick, uint32_t slot)
{
    if (voxels_.size() >= size_t(kNoRecord) - 1) throw std::length_error("voxel store: 2^32 - 2 voxels");
    const uint32_t i = uint32_t(voxels_.size());
    voxels_.emplace_back();
    where_.push_back((brick << (3 * kBrickBits)) | slot);
    return i;
}

std::vector<uint64_t> VoxelStore::packedKeys() const
{
    std::vector<uint64_t> keys(voxels_.size());
    for (uint32_t i = 0; i < keys.size(); ++i) keys[i] = packedKey(i);
    return keys;
}

void VoxelStore::clear()
{
    brick_index_.clear();
    brick_origin_.clear();
    slots_.clear();
    voxels_.clear();
    where_.clear();
}

void VoxelStore::assign(const std::vector<uint64_t>& keys, std::vector<Voxel> voxels)
{
    if (keys.size() != voxels.size())
        throw std::invalid_argument(fmt::format("{} voxel keys but {} voxels", keys.size(), voxels.size()));
    clear();
    where_.reserve(keys.size());
    for (size_t i = 0; i < keys.size(); ++i)
    {
        const VoxelKey k = VoxelKey::unpack(keys[i]);
        if (k.packed() != keys[i] || !k.inRange())
            throw std::invalid_argument(fmt::format("voxel key at index {} is out of range", i));
        const uint32_t b = brickFor(brickKeyOf(k));
        uint32_t& s = slots_[size_t(b) * kBrickSlots + slotOf(k)];
        if (s != kNoRecord) throw std::invalid_argument(fmt::format("duplicate voxel key at index {}", i));
        s = uint32_t(i);
        where_.push_back((b << (3 * kBrickBits)) | slotOf(k));
    }
    voxels_.assign(voxels.begin(), voxels.end());
}

size_t VoxelStore::memoryBytes() const
{
    // A robin_map bucket holds the pair, its distance to the ideal bucket and a flag.
    constexpr size_t bucket = sizeof(std::pair<uint64_t, uint32_t>) + 8;
    return voxels_.bytesUsed() + where_.bytesUsed() + slots_.bytesUsed() + brick_origin_.capacity() * sizeof(VoxelKey) +
           brick_index_.bucket_count() * bucket;
}

}  // namespace pndt
