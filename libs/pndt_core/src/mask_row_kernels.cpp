#include "mask_row_kernels.h"

#include "map_scratch.h"  // kUnmappedPixel

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#if defined(__x86_64__) || defined(_M_X64)
#include <immintrin.h>
#define PNDT_X86 1
#endif

// A footprint's rows through a row kernel: each version's body, with its own
// kernel inlined (a template could not take the versions' target attributes).
#define PNDT_FOOTPRINT_ROWS(ROW_KERNEL)                                                              \
    uint32_t n = 0;                                                                                  \
    for (int r = fp.r0; r <= fp.r1; ++r)                                                             \
    {                                                                                                \
        int a, b;                                                                                    \
        if (!footprintRow(fp, r, k2, a, b)) continue;                                                \
        const uint32_t row = uint32_t(r) * uint32_t(W);                                              \
        n += ROW_KERNEL(predicted + row, depth + row, a, b, w, row, row_remap[r], out + n);          \
    }                                                                                                \
    return n

// The same with the chords of up to kChordBatch rows computed ahead, four rows a
// step (footprintChordsAvx2): each row's square root and two divisions were a
// latency chain the row's pixels waited on, restarted after every mispredicted
// run change.
#define PNDT_FOOTPRINT_ROWS_BATCHED(ROW_KERNEL)                                                      \
    uint32_t n = 0;                                                                                  \
    alignas(32) int32_t c0s[kChordBatch], c1s[kChordBatch];                                          \
    for (int r_begin = fp.r0; r_begin <= fp.r1; r_begin += kChordBatch)                              \
    {                                                                                                \
        const int rows = std::min(kChordBatch, fp.r1 + 1 - r_begin);                                 \
        footprintChordsAvx2(fp, k2, r_begin, rows, c0s, c1s);                                        \
        for (int j = 0; j < rows; ++j)                                                               \
        {                                                                                            \
            const int a = c0s[j], b = c1s[j];                                                        \
            if (a > b) continue;                                                                     \
            const int r = r_begin + j;                                                               \
            const uint32_t row = uint32_t(r) * uint32_t(W);                                          \
            n += ROW_KERNEL(predicted + row, depth + row, a, b, w, row, row_remap[r], out + n, W);   \
        }                                                                                            \
    }                                                                                                \
    return n

namespace pndt
{
namespace
{
inline bool passes(float d, double z0, double tolerance) { return std::abs(double(d) - z0) <= tolerance; }

/// The pixel at column c starts a new run value q (q != run_p): closes the
/// current run (if it is a passing one) and starts the next.
inline void changeRun(int32_t q, int c, uint32_t row, const int32_t* to_frame, int32_t& run_p, int& run_begin,
                      MaskSpan* out, uint32_t& n)
{
    if (run_p != kUnmappedPixel)
        out[n++] = {row + uint32_t(run_begin), row + uint32_t(c), run_p >= 0 ? to_frame[run_p] : run_p};
    run_p = q;
    run_begin = c;
}

/// Pixels [c0, c1] one at a time, continuing the run state.
inline void scalarPixels(const int32_t* predicted, const float* depth, int c0, int c1, DepthWindow w, uint32_t row,
                         const int32_t* to_frame, int32_t& run_p, int& run_begin, MaskSpan* out, uint32_t& n)
{
    for (int c = c0; c <= c1; ++c)
    {
        const int32_t p = predicted[c];
        const float d = depth[c];
        const int32_t q = p == kUnmappedPixel || !(w.lo <= d && d <= w.hi) ? kUnmappedPixel : p;
        if (q != run_p) changeRun(q, c, row, to_frame, run_p, run_begin, out, n);
    }
}

inline uint32_t closeRow(int c1, uint32_t row, const int32_t* to_frame, int32_t run_p, int run_begin, MaskSpan* out,
                         uint32_t n)
{
    if (run_p != kUnmappedPixel)
        out[n++] = {row + uint32_t(run_begin), row + uint32_t(c1) + 1, run_p >= 0 ? to_frame[run_p] : run_p};
    return n;
}

/// std::nextafter(x, +inf) and (x, -inf) for the floats depthWindow meets (not
/// NaN), by the bits: nextafter is a library call, and depthWindow (once per
/// thing voxel a frame) made eight of them.
inline float stepUp(float x)
{
    if (x == std::numeric_limits<float>::infinity()) return x;
    if (x == 0.f) return std::numeric_limits<float>::denorm_min();
    uint32_t b;
    std::memcpy(&b, &x, sizeof b);
    b = x > 0.f ? b + 1 : b - 1;  // a negative float's magnitude shrinks
    std::memcpy(&x, &b, sizeof x);
    return x;
}
inline float stepDown(float x) { return -stepUp(-x); }
}  // namespace

DepthWindow depthWindow(double z0, double tolerance)
{
    DepthWindow w;
    if (!(tolerance >= 0) || !std::isfinite(z0)) return w;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    // The rounded bounds lie within an ulp or two of the exact ends: step each
    // inwards until it passes, then outwards while its neighbour passes.
    float lo = float(z0 - tolerance), hi = float(z0 + tolerance);
    while (lo <= hi && lo < kInf && !passes(lo, z0, tolerance)) lo = stepUp(lo);
    while (hi >= lo && hi > -kInf && !passes(hi, z0, tolerance)) hi = stepDown(hi);
    // No float passes (e.g. tolerance 0 and z0 not a float, or z0 beyond the floats).
    if (!(lo <= hi) || !passes(lo, z0, tolerance) || !passes(hi, z0, tolerance)) return w;
    while (lo > -kInf && passes(stepDown(lo), z0, tolerance)) lo = stepDown(lo);
    while (hi < kInf && passes(stepUp(hi), z0, tolerance)) hi = stepUp(hi);
    w.lo = lo;
    w.hi = hi;
    return w;
}

uint32_t maskRowScalar(const int32_t* predicted, const float* depth, int c0, int c1, DepthWindow w, uint32_t row,
                       const int32_t* to_frame, MaskSpan* out)
{
    uint32_t n = 0;
    int32_t run_p = kUnmappedPixel;
    int run_begin = 0;
    scalarPixels(predicted, depth, c0, c1, w, row, to_frame, run_p, run_begin, out, n);
    return closeRow(c1, row, to_frame, run_p, run_begin, out, n);
}

#ifdef PNDT_X86
constexpr int kChordBatch = 16;  // a multiple of 4

/// footprintRow of rows [r_begin, r_begin + rows) (rows <= kChordBatch), four a
/// step: c0s[j] > c1s[j] where row r_begin + j has no chord. The scalar
/// version's operations in its order, each exact IEEE arithmetic (no fused
/// multiply-adds: the core library builds with -ffp-contract=off), so the
/// chords are the same to the pixel.
__attribute__((target("avx2"), always_inline)) inline void footprintChordsAvx2(const MaskFootprint& fp, double k2,
                                                                                int r_begin, int rows, int32_t* c0s,
                                                                                int32_t* c1s)
{
    if (!fp.ellipse)
    {
        for (int j = 0; j < rows; ++j)
        {
            c0s[j] = fp.c0;
            c1s[j] = fp.c1;
        }
        return;
    }
    const __m256d v0 = _mm256_set1_pd(fp.v0), u0 = _mm256_set1_pd(fp.u0), k2v = _mm256_set1_pd(k2);
    const __m256d qa = _mm256_set1_pd(fp.s00), s01x2 = _mm256_set1_pd(2 * fp.s01), s11 = _mm256_set1_pd(fp.s11);
    const __m256d qa4 = _mm256_set1_pd(4 * fp.s00), den = _mm256_set1_pd(2 * fp.s00);
    const __m256d zero = _mm256_setzero_pd(), sign = _mm256_set1_pd(-0.0);
    const __m256d big = _mm256_set1_pd(1.0e9), small = _mm256_set1_pd(-1.0e9);
    const __m128i box_c0 = _mm_set1_epi32(fp.c0), box_c1 = _mm_set1_epi32(fp.c1);
    for (int j = 0; j < rows; j += 4)
    {
        const __m256d dv = _mm256_sub_pd(_mm256_cvtepi32_pd(_mm_add_epi32(_mm_set1_epi32(r_begin + j),
                                                                            _mm_setr_epi32(0, 1, 2, 3))),
                                         v0);
        const __m256d qb = _mm256_mul_pd(s01x2, dv);
        const __m256d qc = _mm256_sub_pd(_mm256_mul_pd(_mm256_mul_pd(s11, dv), dv), k2v);
        const __m256d disc = _mm256_sub_pd(_mm256_mul_pd(qb, qb), _mm256_mul_pd(qa4, qc));
        // disc >= 0 and qa > 0, ordered: false for NaN, as the scalar test.
        const __m256d ok = _mm256_and_pd(_mm256_cmp_pd(disc, zero, _CMP_GE_OQ), _mm256_cmp_pd(qa, zero, _CMP_GT_OQ));
        const __m256d root = _mm256_sqrt_pd(_mm256_and_pd(disc, ok));
        const __m256d neg_qb = _mm256_xor_pd(qb, sign);
        const __m256d lo = _mm256_round_pd(_mm256_add_pd(u0, _mm256_div_pd(_mm256_sub_pd(neg_qb, root), den)),
                                           _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);
        const __m256d hi = _mm256_round_pd(_mm256_add_pd(u0, _mm256_div_pd(_mm256_add_pd(neg_qb, root), den)),
                                           _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
        // Rows without a chord: c0 = 1e9 > c1 = -1e9. clampedPixel: max(-1e9,
        // min(1e9, x)) - min_pd / max_pd return their second operand for NaN, as
        // std::min / std::max return their first.
        const __m256d lo_or_none = _mm256_blendv_pd(big, lo, ok), hi_or_none = _mm256_blendv_pd(small, hi, ok);
        const __m128i a = _mm256_cvttpd_epi32(_mm256_max_pd(_mm256_min_pd(lo_or_none, big), small));
        const __m128i b = _mm256_cvttpd_epi32(_mm256_max_pd(_mm256_min_pd(hi_or_none, big), small));
        const __m128i c0 = _mm_max_epi32(box_c0, a), c1 = _mm_min_epi32(box_c1, b);
        _mm_store_si128(reinterpret_cast<__m128i*>(c0s + j), c0);
        _mm_store_si128(reinterpret_cast<__m128i*>(c1s + j), c1);
    }
}

__attribute__((target("avx2"), always_inline)) inline uint32_t maskRowAvx2Body(const int32_t* predicted,
                                                                                const float* depth, int c0, int c1,
                                                                                DepthWindow w, uint32_t row,
                                                                                const int32_t* to_frame, MaskSpan* out,
                                                                                int readable)
{
    uint32_t n = 0;
    int32_t run_p = kUnmappedPixel;
    int run_begin = 0;
    const __m256 lo = _mm256_set1_ps(w.lo), hi = _mm256_set1_ps(w.hi);
    const __m256i unmapped = _mm256_set1_epi32(kUnmappedPixel);
    const __m256i shift = _mm256_setr_epi32(7, 0, 1, 2, 3, 4, 5, 6);  // lane i takes lane i - 1 (lane 0: lane 7)
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    alignas(32) int32_t qs[8];
    for (int c = c0; c <= c1; c += 8)
    {
        // Lanes past c1 take the run's value and their changes are dropped. Plain
        // loads while the 8 pixels lie within the image row (`readable` columns:
        // the footprint kernel passes the width), masked ones only at its right
        // edge: the masked loads held the loop (~13 % of the footprint kernel).
        const __m256i in = _mm256_cmpgt_epi32(_mm256_set1_epi32(c1 + 1 - c), lane);
        __m256i p;
        __m256 d;
        if (c + 8 <= readable)
        {
            p = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(predicted + c));
            d = _mm256_loadu_ps(depth + c);
        }
        else
        {
            p = _mm256_maskload_epi32(predicted + c, in);
            d = _mm256_maskload_ps(depth + c, in);
        }
        // Ordered compares: NaN fails.
        const __m256 ok = _mm256_and_ps(_mm256_cmp_ps(lo, d, _CMP_LE_OQ), _mm256_cmp_ps(d, hi, _CMP_LE_OQ));
        const __m256i run = _mm256_set1_epi32(run_p);
        const __m256i q = _mm256_blendv_epi8(run, _mm256_blendv_epi8(unmapped, p, _mm256_castps_si256(ok)), in);
        // The value before each lane: the previous lane, and the run for lane 0.
        const __m256i prev = _mm256_blend_epi32(_mm256_permutevar8x32_epi32(q, shift), run, 1);
        const __m256i changed = _mm256_andnot_si256(_mm256_cmpeq_epi32(q, prev), in);
        uint32_t change = uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(changed)));
        if (!change) continue;
        _mm256_store_si256(reinterpret_cast<__m256i*>(qs), q);
        while (change)
        {
            const int j = __builtin_ctz(change);
            change &= change - 1;
            changeRun(qs[j], c + j, row, to_frame, run_p, run_begin, out, n);
        }
    }
    return closeRow(c1, row, to_frame, run_p, run_begin, out, n);
}

__attribute__((target("avx512f"), always_inline)) inline uint32_t maskRowAvx512Body(const int32_t* predicted,
                                                                                    const float* depth, int c0, int c1,
                                                                                    DepthWindow w, uint32_t row,
                                                                                    const int32_t* to_frame,
                                                                                    MaskSpan* out, int /*readable*/)
{
    uint32_t n = 0;
    int32_t run_p = kUnmappedPixel;
    int run_begin = 0;
    const __m512 lo = _mm512_set1_ps(w.lo), hi = _mm512_set1_ps(w.hi);
    const __m512i unmapped = _mm512_set1_epi32(kUnmappedPixel);
    alignas(64) int32_t qs[16];
    for (int c = c0; c <= c1; c += 16)
    {
        // The last step loads only the row's remaining pixels; the lanes beyond
        // take the run's value, so they change nothing.
        const int left = c1 + 1 - c;
        const __mmask16 in = left >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << left) - 1);
        const __m512i p = _mm512_maskz_loadu_epi32(in, predicted + c);
        const __m512 d = _mm512_maskz_loadu_ps(in, depth + c);
        const __mmask16 ok = _mm512_mask_cmp_ps_mask(_mm512_cmp_ps_mask(lo, d, _CMP_LE_OQ), d, hi, _CMP_LE_OQ) & in;
        const __m512i run = _mm512_set1_epi32(run_p);
        const __m512i q = _mm512_mask_blend_epi32(in, run, _mm512_mask_blend_epi32(ok, unmapped, p));
        // The value before each lane: the previous lane, and the run for lane 0.
        const __m512i prev = _mm512_mask_alignr_epi32(run, 0xFFFF, q, run, 15);  // (unmasked: a GCC 12 warning)
        uint32_t change = _mm512_mask_cmpneq_epi32_mask(in, q, prev);
        if (!change) continue;
        _mm512_store_si512(qs, q);
        while (change)
        {
            const int j = __builtin_ctz(change);
            change &= change - 1;
            changeRun(qs[j], c + j, row, to_frame, run_p, run_begin, out, n);
        }
    }
    return closeRow(c1, row, to_frame, run_p, run_begin, out, n);
}

__attribute__((target("avx2"))) static uint32_t maskRowAvx2Impl(const int32_t* predicted, const float* depth, int c0,
                                                                 int c1, DepthWindow w, uint32_t row,
                                                                 const int32_t* to_frame, MaskSpan* out)
{
    return maskRowAvx2Body(predicted, depth, c0, c1, w, row, to_frame, out, c1 + 1);
}
__attribute__((target("avx512f"))) static uint32_t maskRowAvx512Impl(const int32_t* predicted, const float* depth,
                                                                     int c0, int c1, DepthWindow w, uint32_t row,
                                                                     const int32_t* to_frame, MaskSpan* out)
{
    return maskRowAvx512Body(predicted, depth, c0, c1, w, row, to_frame, out, c1 + 1);
}

// The footprint's rows in one call, the row kernel inlined: a thing voxel at
// 5 cm covers ~9 pixels of ~11 rows, so a call per row cost more than its pixels.
__attribute__((target("avx2"))) static uint32_t maskFootprintAvx2Impl(const MaskFootprint& fp, double k2,
                                                                       const int32_t* predicted, const float* depth,
                                                                       int W, DepthWindow w,
                                                                       const int32_t* const* row_remap, MaskSpan* out)
{
    PNDT_FOOTPRINT_ROWS_BATCHED(maskRowAvx2Body);
}
__attribute__((target("avx512f"))) static uint32_t maskFootprintAvx512Impl(const MaskFootprint& fp, double k2,
                                                                           const int32_t* predicted,
                                                                           const float* depth, int W, DepthWindow w,
                                                                           const int32_t* const* row_remap,
                                                                           MaskSpan* out)
{
    PNDT_FOOTPRINT_ROWS_BATCHED(maskRowAvx512Body);
}

MaskRowFn maskRowAvx2()
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") ? &maskRowAvx2Impl : nullptr;
}

MaskRowFn maskRowAvx512()
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") ? &maskRowAvx512Impl : nullptr;
}
MaskFootprintFn maskFootprintAvx2()
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") ? &maskFootprintAvx2Impl : nullptr;
}

MaskFootprintFn maskFootprintAvx512()
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") ? &maskFootprintAvx512Impl : nullptr;
}
#else
MaskRowFn maskRowAvx2() { return nullptr; }
MaskRowFn maskRowAvx512() { return nullptr; }
MaskFootprintFn maskFootprintAvx2() { return nullptr; }
MaskFootprintFn maskFootprintAvx512() { return nullptr; }
#endif

uint32_t maskFootprintScalar(const MaskFootprint& fp, double k2, const int32_t* predicted, const float* depth, int W,
                             DepthWindow w, const int32_t* const* row_remap, MaskSpan* out)
{
    PNDT_FOOTPRINT_ROWS(maskRowScalar);
}

MaskFootprintFn bestMaskFootprint()
{
    const SimdCap cap = simdCap();
    if (const MaskFootprintFn avx512 = maskFootprintAvx512(); avx512 && cap == SimdCap::Avx512) return avx512;
    if (const MaskFootprintFn avx2 = maskFootprintAvx2(); avx2 && cap >= SimdCap::Avx2) return avx2;
    return &maskFootprintScalar;
}

MaskRowFn bestMaskRow()
{
    const SimdCap cap = simdCap();
    if (const MaskRowFn avx512 = maskRowAvx512(); avx512 && cap == SimdCap::Avx512) return avx512;
    if (const MaskRowFn avx2 = maskRowAvx2(); avx2 && cap >= SimdCap::Avx2) return avx2;
    return &maskRowScalar;
}

#undef PNDT_FOOTPRINT_ROWS
#undef PNDT_FOOTPRINT_ROWS_BATCHED

}  // namespace pndt
