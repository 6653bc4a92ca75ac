// Sparse voxel storage in bricks. Space is cut into bricks of 8x8x8 voxels; a
// hash maps a brick's coordinates to its dense slot table, which maps each of
// the 512 voxels to its index in one contiguous voxel array (or kNoRecord).
// Voxel indices are dense and stable, in creation order, so the rest of the map
// (label pools, propagation, serialisation, callers) addresses voxels by index.
// Voxels are never erased: a voxel once seen free stays known-free.
//
// One hash lookup per brick instead of per voxel: a ray or an image row stays
// in one brick for several voxels, so the hot paths cache the brick and index
// its slot table directly (brickOf / slotsOf).
#pragma once

#include <pndt/record_pool.h>
#include <pndt/voxel.h>
#include <pndt/voxel_key.h>
#include <tsl/robin_map.h>

#include <algorithm>
#include <vector>

namespace pndt
{
class VoxelStore
{
   public:
    static constexpr int kBrickBits = 3;
    static constexpr int32_t kBrickEdge = 1 << kBrickBits;
    static constexpr uint32_t kBrickSlots = 1u << (3 * kBrickBits);
    /// Brick index and slot share one 32-bit locator per voxel.
    static constexpr uint32_t kMaxBricks = 1u << (32 - 3 * kBrickBits);

    /// Packed coordinates of the brick that holds `k`.
    static uint64_t brickKeyOf(const VoxelKey& k)
    {
        return VoxelKey{k.x >> kBrickBits, k.y >> kBrickBits, k.z >> kBrickBits}.packed();
    }
    /// Position of `k` inside its brick (0..511).
    static uint32_t slotOf(const VoxelKey& k)
    {
        constexpr int32_t m = kBrickEdge - 1;
        return uint32_t(k.x & m) | (uint32_t(k.y & m) << kBrickBits) | (uint32_t(k.z & m) << (2 * kBrickBits));
    }

    uint32_t find(const VoxelKey& k) const
    {
        const uint32_t b = brickOf(brickKeyOf(k));
        return b == kNoRecord ? kNoRecord : slots_[size_t(b) * kBrickSlots + slotOf(k)];
    }
    /// Index of the voxel at `k`, creating an empty one (and its brick) if needed.
    /// Throws std::length_error past kMaxBricks bricks or 2^32-2 voxels.
    uint32_t findOrCreate(const VoxelKey& k) { return findOrCreateInBrick(brickFor(brickKeyOf(k)), slotOf(k)); }

    // ---- brick-level access for the hot paths
    /// Brick index of packed brick coordinates, or kNoRecord.
    uint32_t brickOf(uint64_t brick_key) const
    {
        const auto it = brick_index_.find(brick_key);
        return it == brick_index_.end() ? kNoRecord : it->second;
    }
    /// Brick index, creating the (empty) brick if needed.
    uint32_t brickFor(uint64_t brick_key);
    /// The brick's 512 voxel indices (kNoRecord = no voxel). Invalidated when a
    /// brick is created.
    const uint32_t* slotsOf(uint32_t brick) const { return &slots_[size_t(brick) * kBrickSlots]; }
    uint32_t findOrCreateInBrick(uint32_t brick, uint32_t slot)
    {
        uint32_t& s = slots_[size_t(brick) * kBrickSlots + slot];
        if (s == kNoRecord) s = create(brick, slot);
        return s;
    }
    size_t brickCount() const { return brick_origin_.size(); }

    // ---- voxels by index
    size_t size() const { return voxels_.size(); }
    bool empty() const { return voxels_.empty(); }
    Voxel& operator[](uint32_t i) { return voxels_[i]; }
    const Voxel& operator[](uint32_t i) const { return voxels_[i]; }
    VoxelKey key(uint32_t i) const
    {
        const uint32_t w = where_[i];
        const VoxelKey& o = brick_origin_[w >> (3 * kBrickBits)];
        constexpr uint32_t m = kBrickEdge - 1;
        return {o.x + int32_t(w & m), o.y + int32_t((w >> kBrickBits) & m), o.z + int32_t((w >> (2 * kBrickBits)) & m)};
    }
    uint64_t packedKey(uint32_t i) const { return key(i).packed(); }
    /// Packed keys of all voxels, by index (computed: the store keeps 4-byte locators).
    std::vector<uint64_t> packedKeys() const;
    const RecordPool<Voxel>& voxels() const { return voxels_; }

    void clear();
    /// Rebuilds the store from parallel arrays (deserialisation); bricks are
    /// created in order of their first voxel, as during mapping. Throws
    /// std::invalid_argument on size mismatch, keys out of range or duplicates.
    void assign(const std::vector<uint64_t>& keys, std::vector<Voxel> voxels);

    /// Bytes held by the voxels, their locators, the brick slot tables and the
    /// brick hash (the pools' pages in use, the hash by capacity).
    size_t memoryBytes() const;

   private:
    uint32_t create(uint32_t brick, uint32_t slot);

    tsl::robin_map<uint64_t, uint32_t, PackedKeyHash> brick_index_;  ///< packed brick key -> brick
    std::vector<VoxelKey> brick_origin_;  ///< per brick: key of its voxel (0,0,0); small, so on the heap
    RecordPool<uint32_t> slots_;         ///< per brick 512 voxel indices
    RecordPool<Voxel> voxels_;
    RecordPool<uint32_t> where_;         ///< per voxel: brick << 9 | slot
};

}  // namespace pndt
