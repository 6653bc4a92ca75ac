// First phase of the pixel projection, one image row at a time: per pixel its
// packed voxel key (or a special key) and its sample's quantised offset inside
// the voxel. Branch-free, in a scalar, an SSE2, an AVX2 and an AVX-512 version
// that give the same bits (the same double operations, no fused multiply-add),
// chosen at run time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pndt
{
/// Samples are summed as integers: offsets inside the voxel in units of
/// voxel_size / 2^kSampleBits (0.1 um at 10 cm; sensor noise is ~1 mm).
/// Integer sums do not depend on the order of the additions, so any split of
/// the image over threads gives bit-identical shapes. Limits that keep every
/// sum exact: a voxel gets < 2^25 samples per frame (int64 sums of squares),
/// and an image row has < 2^15 pixels (a row's sums are kept in doubles);
/// validateFrame() enforces both through the image size.
constexpr int kSampleBits = 20;
constexpr double kSampleScale = double(1 << kSampleBits);
constexpr int64_t kSampleHalf = int64_t(1) << (kSampleBits - 1);

constexpr uint64_t kInvalidKey = ~uint64_t(0);    ///< zero, negative or non-finite depth
constexpr uint64_t kOverRangeKey = ~uint64_t(1);  ///< beyond max_range
constexpr uint64_t kOutsideKey = ~uint64_t(2);    ///< outside the grid
constexpr uint64_t kFirstSpecialKey = kOutsideKey;
constexpr uint64_t kNoKey = ~uint64_t(3);         ///< matches no pixel (real keys use 63 bits)

/// Per-frame constants: for pixel (r, c) at depth z,
///   G = t + z * (row[r] + col[c])   (per axis)
/// is (grid coordinate + 2^20) * 2^kSampleBits, >= 0 inside the grid: its
/// integer part holds the packed key field above kSampleBits and the offset
/// inside the voxel below.
struct ProjectionSetup
{
    double t[3] = {0, 0, 0};
    std::vector<double> col[3];  ///< per column, per axis
    std::vector<double> row;     ///< per row, 3 doubles
    double max_range = 0;
    bool inside = false;         ///< the frustum lies inside the grid: no per-pixel range test
};

/// One image row after the first phase.
struct RowBuffer
{
    std::vector<uint64_t> key;  ///< packed voxel key or a special key, per pixel
    std::vector<double> q[3];   ///< offset inside the voxel in sample units, centred, per axis

    void resize(int width)
    {
        key.resize(size_t(width));
        for (auto& v : q) v.resize(size_t(width));
    }
};

using ProjectRowFn = void (*)(const ProjectionSetup& P, const double* row_a, const float* depth, int c0, int c1,
                              RowBuffer& out);
/// Pixels [c0, c1) of a row; `row_a` = &P.row[3 * r].
void projectRowScalar(const ProjectionSetup& P, const double* row_a, const float* depth, int c0, int c1,
                      RowBuffer& out);
void projectRowSse2(const ProjectionSetup& P, const double* row_a, const float* depth, int c0, int c1, RowBuffer& out);
/// nullptr when the CPU (or the compiler) has no AVX2.
ProjectRowFn projectRowAvx2();
/// nullptr when the CPU (or the compiler) has no AVX-512 F and DQ.
ProjectRowFn projectRowAvx512();
/// The widest SIMD the per-pixel kernels may use (if the CPU has it):
/// PNDT_PROJECTION_KERNEL=scalar|sse2|avx2 caps it, for tests and measurements.
enum class SimdCap
{
    Scalar,
    Sse2,
    Avx2,
    Avx512
};
SimdCap simdCap();
/// Sets the cap for the maps' next frames (tests: every kernel gives the same map).
void setSimdCap(SimdCap cap);
/// The fastest version this CPU runs, within simdCap().
ProjectRowFn bestProjectRow();

}  // namespace pndt
