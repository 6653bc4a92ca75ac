#include "projection_kernels.h"

#include <pndt/voxel_key.h>

#include <atomic>
#include <cstdlib>
#include <string>

#if defined(__x86_64__) || defined(_M_X64)
#include <immintrin.h>
#define PNDT_X86 1
#endif

namespace pndt
{
namespace
{
constexpr int64_t kMask = (int64_t(1) << kSampleBits) - 1;
constexpr double kInvScale = 1.0 / kSampleScale;   // exact: a power of two
constexpr int32_t kFieldMax = (1 << 21) - 1;        // key field range inside the grid: [1, kFieldMax]
constexpr float kFloatMax = 3.0e38f;                // below: finite
}  // namespace

void projectRowScalar(const ProjectionSetup& P, const double* a, const float* depth, int c0, int c1, RowBuffer& out)
{
    for (int c = c0; c < c1; ++c)
    {
        const float zf = depth[c];
        const bool valid = zf > 0.f && zf <= kFloatMax;  // false for NaN and inf
        const bool in_range = double(zf) <= P.max_range;
        const double z = valid && in_range ? double(zf) : 0.0;
        int64_t k[3];
        double q[3];
        bool inside = true;
        for (int i = 0; i < 3; ++i)
        {
            const double G = P.t[i] + z * (a[i] + P.col[i][size_t(c)]);
            // K = floor(G / 2^18), the offset the rest; both exact (see the SIMD versions).
            const double kd = G * kInvScale;
            const bool ok = kd >= 1.0 && kd < double(kFieldMax + 1);
            inside = inside && ok;
            const int64_t K = ok ? int64_t(kd) : 0;
            const double frac = ok ? G - double(K) * kSampleScale : 0.0;
            k[i] = K;
            q[i] = double(int64_t(frac) - kSampleHalf);
        }
        inside = inside || P.inside;
        const uint64_t pk = uint64_t(k[0]) | (uint64_t(k[1]) << 21) | (uint64_t(k[2]) << 42);
        out.key[size_t(c)] = !valid ? kInvalidKey : !in_range ? kOverRangeKey : !inside ? kOutsideKey : pk;
        for (int i = 0; i < 3; ++i) out.q[i][size_t(c)] = q[i];
    }
}

#ifdef PNDT_X86
void projectRowSse2(const ProjectionSetup& P, const double* a, const float* depth, int c0, int c1, RowBuffer& out)
{
    const __m128d zero = _mm_setzero_pd(), fmax = _mm_set1_pd(double(kFloatMax)), rmax = _mm_set1_pd(P.max_range);
    const __m128d inv = _mm_set1_pd(kInvScale), scale = _mm_set1_pd(kSampleScale), half = _mm_set1_pd(double(kSampleHalf));
    const __m128i one = _mm_set1_epi32(1), fieldmax = _mm_set1_epi32(kFieldMax);
    const __m128i all = _mm_set1_epi32(-1);
    const __m128i inside_all = P.inside ? all : _mm_setzero_si128();
    const __m128i invalid_key = _mm_set1_epi64x(int64_t(kInvalidKey)), over_key = _mm_set1_epi64x(int64_t(kOverRangeKey)),
                  outside_key = _mm_set1_epi64x(int64_t(kOutsideKey));
    __m128d t[3], av[3];
    for (int i = 0; i < 3; ++i)
    {
        t[i] = _mm_set1_pd(P.t[i]);
        av[i] = _mm_set1_pd(a[i]);
    }
    int c = c0;
    for (; c + 2 <= c1; c += 2)
    {
        const __m128d zf = _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(depth + c))));
        const __m128d valid = _mm_and_pd(_mm_cmpgt_pd(zf, zero), _mm_cmple_pd(zf, fmax));
        const __m128d in_range = _mm_cmple_pd(zf, rmax);
        const __m128d z = _mm_and_pd(zf, _mm_and_pd(valid, in_range));
        __m128i K[3];
        __m128i inside = all;
        for (int i = 0; i < 3; ++i)
        {
            const __m128d G = _mm_add_pd(t[i], _mm_mul_pd(z, _mm_add_pd(av[i], _mm_loadu_pd(&P.col[i][size_t(c)]))));
            const __m128i k = _mm_cvttpd_epi32(_mm_mul_pd(G, inv));  // 2 x int32 (0x80000000 if huge)
            const __m128i ok = _mm_and_si128(_mm_cmpgt_epi32(k, _mm_sub_epi32(one, one)),
                                             _mm_cmpgt_epi32(_mm_add_epi32(fieldmax, one), k));
            inside = _mm_and_si128(inside, ok);
            const __m128i kk = _mm_and_si128(k, ok);
            const __m128d frac = _mm_and_pd(_mm_sub_pd(G, _mm_mul_pd(_mm_cvtepi32_pd(kk), scale)),
                                            _mm_castsi128_pd(_mm_unpacklo_epi32(ok, ok)));
            const __m128d q = _mm_sub_pd(_mm_cvtepi32_pd(_mm_cvttpd_epi32(frac)), half);
            _mm_storeu_pd(&out.q[i][size_t(c)], q);
            K[i] = _mm_unpacklo_epi32(kk, _mm_setzero_si128());  // 2 x uint64
        }
        inside = _mm_or_si128(_mm_unpacklo_epi32(inside, inside), inside_all);
        __m128i pk = _mm_or_si128(K[0], _mm_or_si128(_mm_slli_epi64(K[1], 21), _mm_slli_epi64(K[2], 42)));
        // Special keys, the strongest reason last.
        const auto select = [](__m128i mask, __m128i a_, __m128i b_) {
            return _mm_or_si128(_mm_and_si128(mask, a_), _mm_andnot_si128(mask, b_));
        };
        pk = select(inside, pk, outside_key);
        pk = select(_mm_castpd_si128(in_range), pk, over_key);
        pk = select(_mm_castpd_si128(valid), pk, invalid_key);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(&out.key[size_t(c)]), pk);
    }
    projectRowScalar(P, a, depth, c, c1, out);
}

// No int <-> double conversions (two micro-ops each on some cores, four per
// axis before): G < 2^53 truncated (vroundpd), plus 2^52 puts its integer
// part in the low mantissa bits, where the key field (bits 20..40) and the
// offset (bits 0..19) are read with integer masks; the offset goes back to a
// double with the same 2^52 trick. The same numbers as the scalar version:
// trunc(G) - K 2^20 is trunc(G - K 2^20), and every step is exact.
// `inside`: the frustum lies in the grid (ProjectionSetup::inside), so every
// lane passes the grid test: the body leaves it out (a fifth of its operations).
__attribute__((target("avx2"), always_inline)) inline void projectRowAvx2Body(const ProjectionSetup& P, const double* a,
                                                                               const float* depth, int c0, int c1,
                                                                               RowBuffer& out, const bool inside)
{
    const __m256d zero = _mm256_setzero_pd(), fmax = _mm256_set1_pd(double(kFloatMax)),
                  rmax = _mm256_set1_pd(P.max_range);
    const __m256d grid_lo = _mm256_set1_pd(kSampleScale),
                  grid_hi = _mm256_set1_pd(double(kFieldMax + 1) * kSampleScale);  // 2^41: exact
    const __m256d two52 = _mm256_set1_pd(4503599627370496.0);                                // 2^52
    const __m256d two52_half = _mm256_set1_pd(4503599627370496.0 + double(kSampleHalf));    // exact
    const __m256i two52_bits = _mm256_castpd_si256(two52);
    const __m256i offset_mask = _mm256_set1_epi64x(kMask);
    const __m256i field_mask[3] = {_mm256_set1_epi64x(kFieldMax), _mm256_set1_epi64x(int64_t(kFieldMax) << 21),
                                   _mm256_set1_epi64x(int64_t(kFieldMax) << 42)};
    const __m256i invalid_key = _mm256_set1_epi64x(int64_t(kInvalidKey)),
                  over_key = _mm256_set1_epi64x(int64_t(kOverRangeKey)),
                  outside_key = _mm256_set1_epi64x(int64_t(kOutsideKey));
    __m256d t[3], av[3];
    for (int i = 0; i < 3; ++i)
    {
        t[i] = _mm256_set1_pd(P.t[i]);
        av[i] = _mm256_set1_pd(a[i]);
    }
    int c = c0;
    for (; c + 4 <= c1; c += 4)
    {
        const __m256d zf = _mm256_cvtps_pd(_mm_loadu_ps(depth + c));
        const __m256d valid = _mm256_and_pd(_mm256_cmp_pd(zf, zero, _CMP_GT_OQ), _mm256_cmp_pd(zf, fmax, _CMP_LE_OQ));
        const __m256d in_range = _mm256_cmp_pd(zf, rmax, _CMP_LE_OQ);
        const __m256d z = _mm256_and_pd(zf, _mm256_and_pd(valid, in_range));
        __m256i K[3];
        __m256i in_grid = _mm256_set1_epi32(-1);
        for (int i = 0; i < 3; ++i)
        {
            const __m256d G =
                _mm256_add_pd(t[i], _mm256_mul_pd(z, _mm256_add_pd(av[i], _mm256_loadu_pd(&P.col[i][size_t(c)]))));
            // G + 2^52 with G truncated: exact for 2^20 <= G < 2^41 (in the grid),
            // trunc(G) in the low bits.
            __m256i bits = _mm256_castpd_si256(
                _mm256_add_pd(_mm256_round_pd(G, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC), two52));
            if (!inside)
            {
                // In the grid: 2^20 <= G < (kFieldMax + 1) 2^20 (false for NaN; see the
                // AVX-512 kernel); lanes outside are zero, as in the scalar version.
                const __m256i ok = _mm256_castpd_si256(
                    _mm256_and_pd(_mm256_cmp_pd(G, grid_lo, _CMP_GE_OQ), _mm256_cmp_pd(G, grid_hi, _CMP_LT_OQ)));
                in_grid = _mm256_and_si256(in_grid, ok);
                bits = _mm256_and_si256(bits, ok);
            }
            // The key field (trunc(G) >> 20, 21 bits) shifted straight to its place in
            // the packed key, 21 i bits up, and masked there.
            static_assert(kSampleBits == 20, "the shifts below: 21 i - kSampleBits");
            const __m256i placed = i == 0   ? _mm256_srli_epi64(bits, 20)
                                   : i == 1 ? _mm256_slli_epi64(bits, 1)
                                            : _mm256_slli_epi64(bits, 22);
            K[i] = _mm256_and_si256(placed, field_mask[i]);
            const __m256d q = _mm256_sub_pd(
                _mm256_castsi256_pd(_mm256_or_si256(_mm256_and_si256(bits, offset_mask), two52_bits)), two52_half);
            _mm256_storeu_pd(&out.q[i][size_t(c)], q);
        }
        __m256i pk = _mm256_or_si256(K[0], _mm256_or_si256(K[1], K[2]));
        if (!inside) pk = _mm256_blendv_epi8(outside_key, pk, in_grid);
        pk = _mm256_blendv_epi8(over_key, pk, _mm256_castpd_si256(in_range));
        pk = _mm256_blendv_epi8(invalid_key, pk, _mm256_castpd_si256(valid));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(&out.key[size_t(c)]), pk);
    }
    projectRowScalar(P, a, depth, c, c1, out);
}

__attribute__((target("avx2"))) static void projectRowAvx2Impl(const ProjectionSetup& P, const double* a,
                                                               const float* depth, int c0, int c1, RowBuffer& out)
{
    if (P.inside)
        projectRowAvx2Body(P, a, depth, c0, c1, out, true);
    else
        projectRowAvx2Body(P, a, depth, c0, c1, out, false);
}

ProjectRowFn projectRowAvx2()
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") ? &projectRowAvx2Impl : nullptr;
}

// Eight pixels at a time, the AVX2 version's arithmetic (no int <-> double
// conversions: on Zen 4 a 512-bit conversion takes two cycles, and the version
// before this one had four per axis) with mask registers.
__attribute__((target("avx512f,avx512dq"))) static void projectRowAvx512Impl(const ProjectionSetup& P,
                                                                              const double* a, const float* depth,
                                                                              int c0, int c1, RowBuffer& out)
{
    const __m512d zero = _mm512_setzero_pd(), fmax = _mm512_set1_pd(double(kFloatMax)),
                  rmax = _mm512_set1_pd(P.max_range);
    const __m512d grid_lo = _mm512_set1_pd(kSampleScale),
                  grid_hi = _mm512_set1_pd(double(kFieldMax + 1) * kSampleScale);  // 2^41: exact
    const __m512d two52 = _mm512_set1_pd(4503599627370496.0);                              // 2^52
    const __m512d two52_half = _mm512_set1_pd(4503599627370496.0 + double(kSampleHalf));  // exact
    const __m512i two52_bits = _mm512_castpd_si512(two52);
    const __m512i field_mask = _mm512_set1_epi64(kFieldMax), offset_mask = _mm512_set1_epi64(kMask);
    const __m512i field_mask1 = _mm512_set1_epi64(int64_t(kFieldMax) << 21),
                  field_mask2 = _mm512_set1_epi64(int64_t(kFieldMax) << 42);
    const __m512i invalid_key = _mm512_set1_epi64(int64_t(kInvalidKey)),
                  over_key = _mm512_set1_epi64(int64_t(kOverRangeKey)),
                  outside_key = _mm512_set1_epi64(int64_t(kOutsideKey));
    const __mmask8 inside_all = P.inside ? 0xFF : 0;
    __m512d t[3], av[3];
    for (int i = 0; i < 3; ++i)
    {
        t[i] = _mm512_set1_pd(P.t[i]);
        av[i] = _mm512_set1_pd(a[i]);
    }
    int c = c0;
    for (; c + 8 <= c1; c += 8)
    {
        // maskz forms: GCC 12's plain ones warn of an uninitialised merge source.
        const __m512d zf = _mm512_maskz_cvtps_pd(0xFF, _mm256_loadu_ps(depth + c));
        const __mmask8 valid = _mm512_cmp_pd_mask(zf, zero, _CMP_GT_OQ) & _mm512_cmp_pd_mask(zf, fmax, _CMP_LE_OQ);
        const __mmask8 in_range = _mm512_cmp_pd_mask(zf, rmax, _CMP_LE_OQ);
        const __m512d z = _mm512_maskz_mov_pd(valid & in_range, zf);
        __m512i K[3];
        __mmask8 inside = 0xFF;
        for (int i = 0; i < 3; ++i)
        {
            const __m512d G =
                _mm512_add_pd(t[i], _mm512_mul_pd(z, _mm512_add_pd(av[i], _mm512_loadu_pd(&P.col[i][size_t(c)]))));
            // In the grid: 1 <= G / 2^20 < kFieldMax + 1 (false for NaN), compared
            // as 2^20 <= G < (kFieldMax + 1) 2^20: the scale is a power of two, so
            // both compares are exact and no multiply is needed.
            const __mmask8 ok =
                _mm512_cmp_pd_mask(G, grid_lo, _CMP_GE_OQ) & _mm512_cmp_pd_mask(G, grid_hi, _CMP_LT_OQ);
            inside &= ok;
            // ok: 2^20 <= G < 2^41, so G + 2^52 rounded towards zero is 2^52 + trunc(G),
            // trunc(G) in its low bits (one add with embedded rounding, not a round and an
            // add). Lanes outside the grid are zero, as in the scalar version.
            const __m512i bits =
                _mm512_castpd_si512(_mm512_maskz_add_round_pd(ok, G, two52, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC));
            // The key field (trunc(G) >> 20, 21 bits) moved straight to its place in the
            // packed key, 21 i bits up: the masks below keep just those bits.
            static_assert(kSampleBits == 20, "the shifts below: 21 i - kSampleBits");
            K[i] = i == 0   ? _mm512_maskz_srli_epi64(0xFF, bits, 20)
                   : i == 1 ? _mm512_maskz_slli_epi64(0xFF, bits, 1)
                            : _mm512_maskz_slli_epi64(0xFF, bits, 22);
            // (bits & offset_mask) | two52_bits in one ternary-logic op (0xEA: (a & b) | c).
            const __m512d q = _mm512_sub_pd(
                _mm512_castsi512_pd(_mm512_ternarylogic_epi64(bits, offset_mask, two52_bits, 0xEA)), two52_half);
            _mm512_storeu_pd(&out.q[i][size_t(c)], q);
        }
        // (K0 & field) | (K1 & field << 21) | (K2 & field << 42), two ternary-logic ops
        // (0xEA: (a & b) | c).
        __m512i pk = _mm512_ternarylogic_epi64(K[1], field_mask1, _mm512_and_si512(K[0], field_mask), 0xEA);
        pk = _mm512_ternarylogic_epi64(K[2], field_mask2, pk, 0xEA);
        pk = _mm512_mask_mov_epi64(outside_key, inside | inside_all, pk);
        pk = _mm512_mask_mov_epi64(over_key, in_range, pk);
        pk = _mm512_mask_mov_epi64(invalid_key, valid, pk);
        _mm512_storeu_si512(&out.key[size_t(c)], pk);
    }
    projectRowScalar(P, a, depth, c, c1, out);
}

ProjectRowFn projectRowAvx512()
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") ? &projectRowAvx512Impl : nullptr;
}
#else
void projectRowSse2(const ProjectionSetup& P, const double* a, const float* depth, int c0, int c1, RowBuffer& out)
{
    projectRowScalar(P, a, depth, c0, c1, out);
}
ProjectRowFn projectRowAvx2() { return nullptr; }
ProjectRowFn projectRowAvx512() { return nullptr; }
#endif

namespace
{
std::atomic<int> g_simd_cap{-1};  // -1: not read from the environment yet
}  // namespace

SimdCap simdCap()
{
    int cap = g_simd_cap.load(std::memory_order_relaxed);
    if (cap < 0)
    {
        const char* e = std::getenv("PNDT_PROJECTION_KERNEL");
        const std::string forced = e ? e : "";
        cap = int(forced == "scalar" ? SimdCap::Scalar
                  : forced == "sse2" ? SimdCap::Sse2
                  : forced == "avx2" ? SimdCap::Avx2
                                     : SimdCap::Avx512);
        g_simd_cap.store(cap, std::memory_order_relaxed);
    }
    return SimdCap(cap);
}

void setSimdCap(SimdCap cap) { g_simd_cap.store(int(cap), std::memory_order_relaxed); }

ProjectRowFn bestProjectRow()
{
    const SimdCap cap = simdCap();
    if (cap == SimdCap::Scalar) return &projectRowScalar;
    if (const ProjectRowFn avx512 = projectRowAvx512(); avx512 && cap == SimdCap::Avx512) return avx512;
    if (const ProjectRowFn avx2 = projectRowAvx2(); avx2 && cap >= SimdCap::Avx2) return avx2;
    return &projectRowSse2;
}

}  // namespace pndt
