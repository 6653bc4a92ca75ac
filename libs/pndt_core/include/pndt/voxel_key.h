// Integer voxel coordinates and their packing into one 64-bit hash key.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

namespace pndt
{
struct VoxelKey
{
    int32_t x = 0, y = 0, z = 0;

    /// 21 bits per axis: +-2^20 voxels, i.e. +-10 km at 1 cm.
    static constexpr int32_t kLimit = 1 << 20;

    bool operator==(const VoxelKey& o) const { return x == o.x && y == o.y && z == o.z; }
    bool operator!=(const VoxelKey& o) const { return !(*this == o); }
    bool inRange() const
    {
        return x > -kLimit && x < kLimit && y > -kLimit && y < kLimit && z > -kLimit && z < kLimit;
    }
    uint64_t packed() const
    {
        constexpr uint64_t mask = (uint64_t(1) << 21) - 1;
        return (uint64_t(x + kLimit) & mask) | ((uint64_t(y + kLimit) & mask) << 21) |
               ((uint64_t(z + kLimit) & mask) << 42);
    }
    static VoxelKey unpack(uint64_t p)
    {
        constexpr uint64_t mask = (uint64_t(1) << 21) - 1;
        return {int32_t(p & mask) - kLimit, int32_t((p >> 21) & mask) - kLimit,
                int32_t((p >> 42) & mask) - kLimit};
    }
};

/// Hash for packed keys. std::hash<uint64_t> is the identity, and hash tables
/// index by the low bits, where only x lives: mix all bits (murmur3 finaliser).
struct PackedKeyHash
{
    size_t operator()(uint64_t k) const
    {
        k ^= k >> 33;
        k *= 0xff51afd7ed558ccdULL;
        k ^= k >> 33;
        k *= 0xc4ceb9fe1a85ec53ULL;
        k ^= k >> 33;
        return size_t(k);
    }
};

/// Maps world coordinates to voxel keys for a given voxel edge length.
class VoxelGrid
{
   public:
    explicit VoxelGrid(double voxel_size = 0.1) : size_(voxel_size), inv_(1.0 / voxel_size) {}
    double voxelSize() const { return size_; }
    /// False for a point whose key keyOf() cannot give (NaN, infinite, or beyond
    /// the key range): callers answer "no voxel there" instead of converting it.
    bool holds(const Eigen::Vector3d& p) const
    {
        const double lim = double(VoxelKey::kLimit - 1);
        const Eigen::Vector3d k = p * inv_;
        return std::abs(k.x()) < lim && std::abs(k.y()) < lim && std::abs(k.z()) < lim;  // NaN compares false
    }
    VoxelKey keyOf(const Eigen::Vector3d& p) const
    {
        return {int32_t(std::floor(p.x() * inv_)), int32_t(std::floor(p.y() * inv_)),
                int32_t(std::floor(p.z() * inv_))};
    }
    Eigen::Vector3d center(const VoxelKey& k) const
    {
        return {(k.x + 0.5) * size_, (k.y + 0.5) * size_, (k.z + 0.5) * size_};
    }
    Eigen::Vector3d minCorner(const VoxelKey& k) const { return {k.x * size_, k.y * size_, k.z * size_}; }

   private:
    double size_;
    double inv_;
};

}  // namespace pndt
