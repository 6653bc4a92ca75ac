#include <pndt/seg/panoptic_postprocess.h>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <ctime>
#include <cmath>
#include <limits>
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "fast_exp.h"

namespace pndt::seg
{
PanopticPostprocessor::PanopticPostprocessor(const ClassSet& classes, std::vector<uint16_t> channel_to_class,
                                             PostprocessOptions options)
    : classes_(classes), channel_to_class_(std::move(channel_to_class)), options_(options)
{
    if (options_.nms_kernel < 1 || options_.nms_kernel % 2 == 0)
        throw InputError(fmt::format("postprocess: nms_kernel must be odd and >= 1 (got {})", options_.nms_kernel));
    if (options_.top_k < 1) throw InputError(fmt::format("postprocess: top_k must be >= 1 (got {})", options_.top_k));
    if (channel_to_class_.empty() || channel_to_class_.size() > 256)
        throw InputError(fmt::format("postprocess: {} semantic channels (1..256 supported)", channel_to_class_.size()));
    for (size_t k = 0; k < channel_to_class_.size(); ++k)
    {
        const uint16_t c = channel_to_class_[k];
        if (!classes_.contains(c))
            throw InputError(fmt::format("postprocess: class id {} is outside the class set (0..{})", c,
                                         classes_.size() - 1));
        channel_is_thing_[k] = classes_.isThing(c) ? 1 : 0;
        channel_class_[k] = c;
    }
}

namespace
{
// Pixel blocks small enough that their slices of all channels (41 × 2048 floats = 328 kB) stay in
// L2 between the max pass and the softmax pass (L1 cannot hold them whatever the block: the
// class planes lie a multiple of 4 kB apart, so one column of a block falls into one L1 set).
constexpr size_t kBlock = 2048;
// The softmax pass decides per sub-block which channels it can leave out.
constexpr size_t kSubBlock = 64;
// The grouping's centre grid: cells of 16 × 16 vote pixels over the image.
constexpr int kGridCell = 16;
constexpr uint32_t kSeveral = 0xffffffffu;  // a grid cell with more than one candidate centre

/// CPU time of the calling thread (ms): what one core spends, whatever else the machine runs.
double threadMs()
{
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

/// n elements of `buf` whose address lies `shift` bytes (mod 4 kB) after `ref`'s: loads from the
/// class planes and stores to the block scratch must not alias in the low 12 address bits.
template <class T>
T* scratch(std::vector<T>& buf, size_t n, const void* ref, size_t shift)
{
    buf.resize(n + 4096 / sizeof(T));
    const size_t b = reinterpret_cast<uintptr_t>(buf.data()) % 4096, r = reinterpret_cast<uintptr_t>(ref) % 4096;
    return buf.data() + ((r + shift + 4096 - b) % 4096) / sizeof(T);
}

/// Largest logit below every pixel's winner that a class may have and still be skipped in S^L.
float skipMargin(float tolerance, int classes)
{
    if (!(tolerance > 0.f) || classes < 2) return std::numeric_limits<float>::infinity();
    return float(std::log(double(classes - 1) / double(tolerance)));
}

// The hot loops, compiled twice (AVX2 + FMA, and the baseline) and picked at load time by the
// CPU: a Debian binary cannot assume AVX2, most robots' CPUs have it.
// Not under ThreadSanitizer: the clones' ifunc resolver runs while the dynamic loader
// relocates the program, before TSan's runtime is set up, and crashed every binary linking
// pndt_seg at start (found by scripts/test_sanitized.sh tsan).
#if defined(__x86_64__) && defined(__GNUC__)
#if defined(__SANITIZE_THREAD__)
#define PNDT_SIMD_CLONES
#else
#define PNDT_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
#define PNDT_HAVE_AVX2_KERNEL 1
#else
#define PNDT_SIMD_CLONES
#define PNDT_HAVE_AVX2_KERNEL 0
#endif

/// Running max and argmax over the channels of pixels [b0, b0 + n) of planar logits (the exact
/// path, for blocks with non-finite values).
PNDT_SIMD_CLONES void blockArgmax(const float* semantic, size_t N, int C, size_t b0, size_t n,
                                  float* __restrict mx, int32_t* __restrict am)
{
    const float* first = semantic + b0;
    for (size_t i = 0; i < n; ++i)
    {
        mx[i] = first[i];
        am[i] = 0;
    }
    for (int c = 1; c < C; ++c)
    {
        const float* __restrict p = semantic + size_t(c) * N + b0;
        for (size_t i = 0; i < n; ++i)
        {
            const float v = p[i], m = mx[i];
            const int32_t take = -int32_t(v > m);
            am[i] = (c & take) | (am[i] & ~take);
            mx[i] = v > m ? v : m;
        }
    }
}

/// S^L = softmax of the winner = 1 / Σ_c exp(l_c − l_max) over all channels (the exact path).
PNDT_SIMD_CLONES void blockSoftmaxScore(const float* semantic, size_t N, int C, size_t b0, size_t n,
                                        const float* __restrict mx, float* __restrict sum, float* __restrict score)
{
    for (size_t i = 0; i < n; ++i) sum[i] = 0.f;
    for (int c = 0; c < C; ++c)
    {
        const float* __restrict p = semantic + size_t(c) * N + b0;
        for (size_t i = 0; i < n; ++i) sum[i] += fastExpNonPositive(p[i] - mx[i]);
    }
    for (size_t i = 0; i < n; ++i) score[i] = 1.f / sum[i];
}

/// One block's max pass: per pixel the max logit and its first channel (as blockArgmax). False
/// if the block holds a non-finite logit (the caller then takes the exact path).
bool blockMaxScalar(const float* semantic, size_t N, int C, size_t b0, size_t n, float* __restrict mx,
                    int32_t* __restrict am)
{
    blockArgmax(semantic, N, C, b0, n, mx, am);
    float acc = 0.f;
    for (int c = 0; c < C; ++c)
    {
        const float* __restrict p = semantic + size_t(c) * N + b0;
        for (size_t i = 0; i < n; ++i) acc += p[i];
    }
    return std::isfinite(acc);
}

/// One sub-block's softmax pass: Σ exp(l − mx) into `sum` over the channels whose largest l − mx
/// over the sub-block is ≥ −skip (the others' terms are all below e^−skip; skip = ∞: all).
/// Returns how many channels it left out.
int blockSoftmaxScalar(const float* semantic, size_t N, int C, size_t b0, size_t n, const float* __restrict mx,
                       float skip, float* __restrict sum)
{
    for (size_t i = 0; i < n; ++i) sum[i] = 0.f;
    int skipped = 0;
    for (int c = 0; c < C; ++c)
    {
        const float* __restrict p = semantic + size_t(c) * N + b0;
        float dmax = -std::numeric_limits<float>::infinity();
        for (size_t i = 0; i < n; ++i) dmax = std::max(dmax, p[i] - mx[i]);
        if (dmax < -skip)
        {
            ++skipped;
            continue;
        }
        for (size_t i = 0; i < n; ++i) sum[i] += fastExpNonPositive(p[i] - mx[i]);
    }
    return skipped;
}

#if PNDT_HAVE_AVX2_KERNEL
#define PNDT_AVX2 __attribute__((target("avx2,fma")))

PNDT_AVX2 inline float hmax(__m256 v)
{
    __m128 m = _mm_max_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    m = _mm_max_ss(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
}

/// fastExpNonPositive, 8 lanes (the same operations; FMA rounds the polynomial once per step).
PNDT_AVX2 inline __m256 exp8(__m256 x)
{
    x = _mm256_max_ps(x, _mm256_set1_ps(-87.f));
    const __m256 t = _mm256_mul_ps(x, _mm256_set1_ps(kExpLog2e));
    const __m256 r = _mm256_add_ps(t, _mm256_set1_ps(kExpRound));
    const __m256 f = _mm256_sub_ps(t, _mm256_sub_ps(r, _mm256_set1_ps(kExpRound)));
    __m256 p = _mm256_fmadd_ps(f, _mm256_set1_ps(kExpC5), _mm256_set1_ps(kExpC4));
    p = _mm256_fmadd_ps(f, p, _mm256_set1_ps(kExpC3));
    p = _mm256_fmadd_ps(f, p, _mm256_set1_ps(kExpC2));
    p = _mm256_fmadd_ps(f, p, _mm256_set1_ps(kExpC1));
    p = _mm256_fmadd_ps(f, p, _mm256_set1_ps(1.f));
    const __m256i bits = _mm256_slli_epi32(_mm256_add_epi32(_mm256_castps_si256(r), _mm256_set1_epi32(127)), 23);
    return _mm256_mul_ps(p, _mm256_castsi256_ps(bits));
}

/// The 41 streams of a block are too many for the hardware prefetchers: each cache line of the
/// max pass asks for the same line of the next block into L2 (a prefetch never faults, also
/// past the end of the tensor). Measured: the max/argmax pass 6.1 → 4.5 ms.
PNDT_AVX2 inline void prefetchNextBlock(const float* p)
{
    _mm_prefetch(reinterpret_cast<const char*>(p + kBlock), _MM_HINT_T1);
}

/// blockMaxScalar for n a multiple of 8.
PNDT_AVX2 bool blockMaxAvx2(const float* semantic, size_t N, int C, size_t b0, size_t n, float* __restrict mx,
                            int32_t* __restrict am)
{
    __m256 acc = _mm256_setzero_ps();
    {
        const float* p = semantic + b0;
        for (size_t i = 0; i < n; i += 8)
        {
            if ((i & 15) == 0) prefetchNextBlock(p + i);
            const __m256 v = _mm256_loadu_ps(p + i);
            _mm256_storeu_ps(mx + i, v);
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(am + i), _mm256_setzero_si256());
            acc = _mm256_add_ps(acc, v);
        }
    }
    for (int c = 1; c < C; ++c)
    {
        const float* p = semantic + size_t(c) * N + b0;
        const __m256 id = _mm256_castsi256_ps(_mm256_set1_epi32(c));
        for (size_t i = 0; i < n; i += 8)
        {
            if ((i & 15) == 0) prefetchNextBlock(p + i);
            const __m256 v = _mm256_loadu_ps(p + i), m = _mm256_loadu_ps(mx + i);
            const __m256 take = _mm256_cmp_ps(v, m, _CMP_GT_OQ);
            float* a = reinterpret_cast<float*>(am + i);
            _mm256_storeu_ps(a, _mm256_blendv_ps(_mm256_loadu_ps(a), id, take));
            _mm256_storeu_ps(mx + i, _mm256_max_ps(v, m));  // v > mx ? v : mx
            acc = _mm256_add_ps(acc, v);
        }
    }
    // Finite iff acc − acc == 0 in every lane (inf − inf and NaN give NaN).
    const __m256 z = _mm256_sub_ps(acc, acc);
    return _mm256_movemask_ps(_mm256_cmp_ps(z, z, _CMP_UNORD_Q)) == 0;
}

/// blockSoftmaxScalar for n a multiple of 8.
PNDT_AVX2 int blockSoftmaxAvx2(const float* semantic, size_t N, int C, size_t b0, size_t n,
                               const float* __restrict mx, float skip, float* __restrict sum)
{
    for (size_t i = 0; i < n; i += 8) _mm256_storeu_ps(sum + i, _mm256_setzero_ps());
    int skipped = 0;
    for (int c = 0; c < C; ++c)
    {
        const float* p = semantic + size_t(c) * N + b0;
        if (skip < std::numeric_limits<float>::infinity())
        {
            // The channel's largest l − mx over the sub-block.
            __m256 dm = _mm256_sub_ps(_mm256_loadu_ps(p), _mm256_loadu_ps(mx));
            for (size_t i = 8; i < n; i += 8)
                dm = _mm256_max_ps(dm, _mm256_sub_ps(_mm256_loadu_ps(p + i), _mm256_loadu_ps(mx + i)));
            if (hmax(dm) < -skip)
            {
                ++skipped;
                continue;
            }
        }
        for (size_t i = 0; i < n; i += 8)
        {
            const __m256 d = _mm256_sub_ps(_mm256_loadu_ps(p + i), _mm256_loadu_ps(mx + i));
            _mm256_storeu_ps(sum + i, _mm256_add_ps(_mm256_loadu_ps(sum + i), exp8(d)));
        }
    }
    return skipped;
}

/// Sixteen pixels' classes (`class_of` their channels') as uint16, from two 8-lane channel vectors.
PNDT_AVX2 inline void storeClasses16(uint16_t* sem, __m256i a_lo, __m256i a_hi, const int32_t* class_of)
{
    const __m256i lo = _mm256_i32gather_epi32(class_of, a_lo, 4), hi = _mm256_i32gather_epi32(class_of, a_hi, 4);
    // packus interleaves the 128-bit halves; the permute puts the 16 values back in order.
    const __m256i packed = _mm256_permute4x64_epi64(_mm256_packus_epi32(lo, hi), 0xD8);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(sem), packed);
}

/// blockPixelsAvx512 in 8 lanes (for CPUs without AVX-512), bit for bit its outputs. AVX2's 16
/// registers hold half a sub-block: the max pass runs over each 32-pixel half in registers
/// (4 × 8 lanes) and leaves max and argmax in L1 scratch; then one pass over the channels per
/// 64-pixel sub-block does the class test and the exponentials, as blockPixelsAvx512 does.
/// Returns false at the first sub-block with a non-finite logit.
PNDT_AVX2 bool blockPixelsAvx2(const float* semantic, size_t N, int C, size_t b0, size_t n, bool softmax, float skip,
                               int& skipped_last, float* __restrict mx, int32_t* __restrict am,
                               const int32_t* class_of, uint16_t* __restrict sem, float* __restrict score)
{
    const int skipped_on_entry = skipped_last;
    const float inf = std::numeric_limits<float>::infinity();
    for (size_t s0 = 0; s0 < n; s0 += kSubBlock)
    {
        const float* base = semantic + b0 + s0;
        __m256 acc = _mm256_setzero_ps();
        for (size_t h = 0; h < kSubBlock; h += 32)
        {
            const float* first = base + h;
            __m256 m0 = _mm256_loadu_ps(first), m1 = _mm256_loadu_ps(first + 8), m2 = _mm256_loadu_ps(first + 16),
                   m3 = _mm256_loadu_ps(first + 24);
            __m256 a0 = _mm256_setzero_ps(), a1 = a0, a2 = a0, a3 = a0;  // channel ids as float bits
            acc = _mm256_add_ps(acc, _mm256_add_ps(_mm256_add_ps(m0, m1), _mm256_add_ps(m2, m3)));
            prefetchNextBlock(first);
            prefetchNextBlock(first + 16);
            for (int c = 1; c < C; ++c)
            {
                const float* p = first + size_t(c) * N;
                prefetchNextBlock(p);
                prefetchNextBlock(p + 16);
                const __m256 id = _mm256_castsi256_ps(_mm256_set1_epi32(c));
                const __m256 v0 = _mm256_loadu_ps(p), v1 = _mm256_loadu_ps(p + 8), v2 = _mm256_loadu_ps(p + 16),
                             v3 = _mm256_loadu_ps(p + 24);
                a0 = _mm256_blendv_ps(a0, id, _mm256_cmp_ps(v0, m0, _CMP_GT_OQ));
                a1 = _mm256_blendv_ps(a1, id, _mm256_cmp_ps(v1, m1, _CMP_GT_OQ));
                a2 = _mm256_blendv_ps(a2, id, _mm256_cmp_ps(v2, m2, _CMP_GT_OQ));
                a3 = _mm256_blendv_ps(a3, id, _mm256_cmp_ps(v3, m3, _CMP_GT_OQ));
                m0 = _mm256_max_ps(v0, m0);
                m1 = _mm256_max_ps(v1, m1);
                m2 = _mm256_max_ps(v2, m2);
                m3 = _mm256_max_ps(v3, m3);
                acc = _mm256_add_ps(acc, _mm256_add_ps(_mm256_add_ps(v0, v1), _mm256_add_ps(v2, v3)));
            }
            float* m = mx + s0 + h;
            _mm256_storeu_ps(m, m0);
            _mm256_storeu_ps(m + 8, m1);
            _mm256_storeu_ps(m + 16, m2);
            _mm256_storeu_ps(m + 24, m3);
            float* a = reinterpret_cast<float*>(am + s0 + h);
            _mm256_storeu_ps(a, a0);
            _mm256_storeu_ps(a + 8, a1);
            _mm256_storeu_ps(a + 16, a2);
            _mm256_storeu_ps(a + 24, a3);
            storeClasses16(sem + s0 + h, _mm256_castps_si256(a0), _mm256_castps_si256(a1), class_of);
            storeClasses16(sem + s0 + h + 16, _mm256_castps_si256(a2), _mm256_castps_si256(a3), class_of);
        }
        // Finite iff acc − acc == 0 in every lane (inf − inf and NaN give NaN).
        const __m256 z = _mm256_sub_ps(acc, acc);
        if (_mm256_movemask_ps(_mm256_cmp_ps(z, z, _CMP_UNORD_Q)) != 0)
        {
            skipped_last = skipped_on_entry;
            return false;
        }
        if (!softmax) continue;
        const float sub_skip = skipped_last > 0 || (s0 / kSubBlock) % 4 == 0 ? skip : inf;
        // One pass over the channels as in blockPixelsAvx512; the sums live in eight registers
        // or spill to L1, which costs less than a second read of the channels.
        const float* m = mx + s0;
        __m256 e[8];
        for (int k = 0; k < 8; ++k) e[k] = _mm256_setzero_ps();
        int skipped = 0;
        const __m256 limit = _mm256_set1_ps(-sub_skip);
        for (int c = 0; c < C; ++c)
        {
            const float* p = base + size_t(c) * N;
            __m256 d[8];
            for (int k = 0; k < 8; ++k) d[k] = _mm256_sub_ps(_mm256_loadu_ps(p + 8 * k), _mm256_loadu_ps(m + 8 * k));
            // Every lane below −skip (a finite sub-block: no NaN to mislead the compare).
            if (sub_skip < inf)
            {
                const __m256 dm = _mm256_max_ps(_mm256_max_ps(_mm256_max_ps(d[0], d[1]), _mm256_max_ps(d[2], d[3])),
                                                _mm256_max_ps(_mm256_max_ps(d[4], d[5]), _mm256_max_ps(d[6], d[7])));
                if (_mm256_movemask_ps(_mm256_cmp_ps(dm, limit, _CMP_GE_OQ)) == 0)
                {
                    ++skipped;
                    continue;
                }
            }
            for (int k = 0; k < 8; ++k) e[k] = _mm256_add_ps(e[k], exp8(d[k]));
        }
        const __m256 one = _mm256_set1_ps(1.f);
        for (int k = 0; k < 8; ++k) _mm256_storeu_ps(score + s0 + 8 * k, _mm256_div_ps(one, e[k]));
        skipped_last = skipped;
    }
    return true;
}

bool cpuHasAvx2()
{
    static const bool yes = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return yes;
}

#define PNDT_AVX512 __attribute__((target("avx512f,avx2,fma")))
// GCC 12 warns of the undefined pass-through inside its own _mm512_max_ps (a false report).
#if defined(__GNUC__) && !defined(__clang__)  // clang has no such warning (and warns of the pragma)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

/// exp8 in 16 lanes (the same operations).
PNDT_AVX512 inline __m512 exp16(__m512 x)
{
    x = _mm512_max_ps(x, _mm512_set1_ps(-87.f));
    const __m512 t = _mm512_mul_ps(x, _mm512_set1_ps(kExpLog2e));
    const __m512 r = _mm512_add_ps(t, _mm512_set1_ps(kExpRound));
    const __m512 f = _mm512_sub_ps(t, _mm512_sub_ps(r, _mm512_set1_ps(kExpRound)));
    __m512 p = _mm512_fmadd_ps(f, _mm512_set1_ps(kExpC5), _mm512_set1_ps(kExpC4));
    p = _mm512_fmadd_ps(f, p, _mm512_set1_ps(kExpC3));
    p = _mm512_fmadd_ps(f, p, _mm512_set1_ps(kExpC2));
    p = _mm512_fmadd_ps(f, p, _mm512_set1_ps(kExpC1));
    p = _mm512_fmadd_ps(f, p, _mm512_set1_ps(1.f));
    const __m512i bits = _mm512_slli_epi32(_mm512_add_epi32(_mm512_castps_si512(r), _mm512_set1_epi32(127)), 23);
    return _mm512_mul_ps(p, _mm512_castsi512_ps(bits));
}

/// blockMaxAvx2 and blockSoftmaxAvx2 of one block (n a multiple of kSubBlock) fused per
/// 64-pixel sub-block held in registers (4 × 16 lanes): the max pass reads the sub-block's
/// slices of all channels from L2 (prefetched a block ahead, as blockMaxAvx2 does) and the
/// softmax pass reads them again from L1 (41 × 256 B), with no per-channel scratch loads and
/// stores. The same operations in the same order per pixel: bit-identical outputs.
/// Also writes each pixel's class (`class_of` its channel's, 256 entries) and, with `softmax`,
/// S^L = 1 / Σ (else only the max pass). Returns false at the first sub-block with a non-finite
/// logit (the caller redoes the block on the exact path; `skipped_last` is then as on entry).
PNDT_AVX512 bool blockPixelsAvx512(const float* semantic, size_t N, int C, size_t b0, size_t n, bool softmax,
                                   float skip, int& skipped_last, float* __restrict mx, int32_t* __restrict am,
                                   const int32_t* class_of, uint16_t* __restrict sem, float* __restrict score)
{
    const int skipped_on_entry = skipped_last;
    const float inf = std::numeric_limits<float>::infinity();
    for (size_t s0 = 0; s0 < n; s0 += kSubBlock)
    {
        const float* base = semantic + b0 + s0;
        __m512 m0 = _mm512_loadu_ps(base), m1 = _mm512_loadu_ps(base + 16), m2 = _mm512_loadu_ps(base + 32),
               m3 = _mm512_loadu_ps(base + 48);
        __m512i a0 = _mm512_setzero_si512(), a1 = a0, a2 = a0, a3 = a0;
        __m512 acc = _mm512_add_ps(_mm512_add_ps(m0, m1), _mm512_add_ps(m2, m3));
        for (int q = 0; q < 64; q += 16) prefetchNextBlock(base + q);
        for (int c = 1; c < C; ++c)
        {
            const float* p = base + size_t(c) * N;
            for (int q = 0; q < 64; q += 16) prefetchNextBlock(p + q);
            const __m512i id = _mm512_set1_epi32(c);
            const __m512 v0 = _mm512_loadu_ps(p), v1 = _mm512_loadu_ps(p + 16), v2 = _mm512_loadu_ps(p + 32),
                         v3 = _mm512_loadu_ps(p + 48);
            a0 = _mm512_mask_mov_epi32(a0, _mm512_cmp_ps_mask(v0, m0, _CMP_GT_OQ), id);
            a1 = _mm512_mask_mov_epi32(a1, _mm512_cmp_ps_mask(v1, m1, _CMP_GT_OQ), id);
            a2 = _mm512_mask_mov_epi32(a2, _mm512_cmp_ps_mask(v2, m2, _CMP_GT_OQ), id);
            a3 = _mm512_mask_mov_epi32(a3, _mm512_cmp_ps_mask(v3, m3, _CMP_GT_OQ), id);
            m0 = _mm512_max_ps(v0, m0);
            m1 = _mm512_max_ps(v1, m1);
            m2 = _mm512_max_ps(v2, m2);
            m3 = _mm512_max_ps(v3, m3);
            acc = _mm512_add_ps(acc, _mm512_add_ps(_mm512_add_ps(v0, v1), _mm512_add_ps(v2, v3)));
        }
        _mm512_storeu_ps(mx + s0, m0);
        _mm512_storeu_ps(mx + s0 + 16, m1);
        _mm512_storeu_ps(mx + s0 + 32, m2);
        _mm512_storeu_ps(mx + s0 + 48, m3);
        _mm512_storeu_si512(am + s0, a0);
        _mm512_storeu_si512(am + s0 + 16, a1);
        _mm512_storeu_si512(am + s0 + 32, a2);
        _mm512_storeu_si512(am + s0 + 48, a3);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(sem + s0), _mm512_cvtepi32_epi16(_mm512_i32gather_epi32(a0, class_of, 4)));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(sem + s0 + 16),
                            _mm512_cvtepi32_epi16(_mm512_i32gather_epi32(a1, class_of, 4)));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(sem + s0 + 32),
                            _mm512_cvtepi32_epi16(_mm512_i32gather_epi32(a2, class_of, 4)));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(sem + s0 + 48),
                            _mm512_cvtepi32_epi16(_mm512_i32gather_epi32(a3, class_of, 4)));
        // Finite iff acc − acc == 0 in every lane (inf − inf and NaN give NaN).
        const __m512 z = _mm512_sub_ps(acc, acc);
        if (_mm512_cmp_ps_mask(z, z, _CMP_UNORD_Q) != 0)
        {
            skipped_last = skipped_on_entry;
            return false;
        }
        if (!softmax) continue;
        const float sub_skip = skipped_last > 0 || (s0 / kSubBlock) % 4 == 0 ? skip : inf;
        __m512 e0 = _mm512_setzero_ps(), e1 = e0, e2 = e0, e3 = e0;
        int skipped = 0;
        for (int c = 0; c < C; ++c)
        {
            const float* p = base + size_t(c) * N;
            const __m512 d0 = _mm512_sub_ps(_mm512_loadu_ps(p), m0), d1 = _mm512_sub_ps(_mm512_loadu_ps(p + 16), m1),
                         d2 = _mm512_sub_ps(_mm512_loadu_ps(p + 32), m2), d3 = _mm512_sub_ps(_mm512_loadu_ps(p + 48), m3);
            // Every lane below −skip (a finite sub-block: no NaN to mislead the compare).
            if (sub_skip < inf && _mm512_cmp_ps_mask(_mm512_max_ps(_mm512_max_ps(d0, d1), _mm512_max_ps(d2, d3)),
                                                     _mm512_set1_ps(-sub_skip), _CMP_GE_OQ) == 0)
            {
                ++skipped;
                continue;
            }
            e0 = _mm512_add_ps(e0, exp16(d0));
            e1 = _mm512_add_ps(e1, exp16(d1));
            e2 = _mm512_add_ps(e2, exp16(d2));
            e3 = _mm512_add_ps(e3, exp16(d3));
        }
        const __m512 one = _mm512_set1_ps(1.f);
        _mm512_storeu_ps(score + s0, _mm512_div_ps(one, e0));
        _mm512_storeu_ps(score + s0 + 16, _mm512_div_ps(one, e1));
        _mm512_storeu_ps(score + s0 + 32, _mm512_div_ps(one, e2));
        _mm512_storeu_ps(score + s0 + 48, _mm512_div_ps(one, e3));
        skipped_last = skipped;
    }
    return true;
}

/// What the grouping of a block reads and writes (see groupBlock).
struct GroupingView
{
    const int32_t* am;          ///< channel per pixel of the block (index − b0)
    size_t b0;                  ///< the block's first pixel
    const int32_t* is_thing;    ///< 0/1 per channel, 256 entries
    bool any_centre;
    const float *dx, *dy;       ///< offsets, output pixels × offset_scale
    float scale, grid_x0, grid_y0, inv_cell, grid_w, grid_h;
    int grid_cols;
    const uint32_t* grid_single;  ///< per cell: its only candidate + 1, or kSeveral
    const uint16_t* sem;
    const float* score;
    const float* centre_score;  ///< S^Z per instance id (0: none)
    uint32_t* inst;
    float* pan;
};

/// The lane-by-lane part of the vector grouping kernels: lanes in `ask` (several candidate
/// centres, or a vote outside the grid) search their centre, then every thing lane votes.
template <int kLanes, class Search, class Vote>
inline void searchAndVoteLanes(uint32_t* zl, const float* vxl, const float* vyl, unsigned ask, unsigned things,
                               const uint16_t* sem, Search& search, Vote& vote)
{
    for (int l = 0; l < kLanes; ++l)
        if (ask >> l & 1) zl[l] = search(vxl[l], vyl[l]);
    for (int l = 0; l < kLanes; ++l)
        if (things >> l & 1) vote(zl[l], sem[l]);
}

/// groupBlock's pixel loop, 16 pixels a step from image pixel i at (x, y) while a step stays
/// in one row: thing pixels vote in a gather of their grid cells; cells with several candidate
/// centres (and votes outside the grid) ask `search(vx, vy)`; votes are counted with `vote(z,
/// class)` lane by lane. The same operations as the scalar loop (the offset product is kept
/// apart from the sum: no fused multiply-add). Returns the pixels done (a multiple of 16).
template <class Search, class Vote>
PNDT_AVX512 size_t groupRunAvx512(const GroupingView& g, size_t i, size_t n, size_t x, size_t W, uint32_t y,
                                  Search&& search, Vote&& vote)
{
    const __m512 iota = _mm512_setr_ps(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512i several = _mm512_set1_epi32(int32_t(kSeveral));
    size_t done = 0;
    for (; i + 16 <= n && x + 16 <= W; i += 16, x += 16, done += 16)
    {
        __mmask16 things = 0;
        if (g.any_centre)
        {
            const __m512i t = _mm512_i32gather_epi32(_mm512_loadu_si512(g.am + (i - g.b0)), g.is_thing, 4);
            things = _mm512_test_epi32_mask(t, t);
        }
        __m512i z = _mm512_setzero_si512();
        if (things)
        {
            __m512 sdx = _mm512_mul_ps(_mm512_set1_ps(g.scale), _mm512_loadu_ps(g.dx + i));
            __m512 sdy = _mm512_mul_ps(_mm512_set1_ps(g.scale), _mm512_loadu_ps(g.dy + i));
            asm("" : "+v"(sdx), "+v"(sdy));  // as the scalar code: round the product, then add
            const __m512 vx = _mm512_add_ps(_mm512_add_ps(_mm512_set1_ps(float(x)), iota), sdx);
            const __m512 vy = _mm512_add_ps(_mm512_set1_ps(float(y)), sdy);
            const __m512 gx = _mm512_mul_ps(_mm512_sub_ps(vx, _mm512_set1_ps(g.grid_x0)), _mm512_set1_ps(g.inv_cell));
            const __m512 gy = _mm512_mul_ps(_mm512_sub_ps(vy, _mm512_set1_ps(g.grid_y0)), _mm512_set1_ps(g.inv_cell));
            const __m512 zero = _mm512_setzero_ps();
            const __mmask16 in = _mm512_cmp_ps_mask(gx, zero, _CMP_GE_OQ) &
                                 _mm512_cmp_ps_mask(gx, _mm512_set1_ps(g.grid_w), _CMP_LT_OQ) &
                                 _mm512_cmp_ps_mask(gy, zero, _CMP_GE_OQ) &
                                 _mm512_cmp_ps_mask(gy, _mm512_set1_ps(g.grid_h), _CMP_LT_OQ) & things;
            const __m512i cell = _mm512_add_epi32(_mm512_mullo_epi32(_mm512_cvttps_epi32(gy), _mm512_set1_epi32(g.grid_cols)),
                                                  _mm512_cvttps_epi32(gx));
            z = _mm512_mask_i32gather_epi32(several, in, cell, g.grid_single, 4);
            z = _mm512_maskz_mov_epi32(things, z);
            const __mmask16 ask = _mm512_cmpeq_epi32_mask(z, several) & things;
            alignas(64) uint32_t zl[16];
            alignas(64) float vxl[16], vyl[16];
            _mm512_store_si512(zl, z);
            if (ask)
            {
                _mm512_store_ps(vxl, vx);
                _mm512_store_ps(vyl, vy);
            }
            searchAndVoteLanes<16>(zl, vxl, vyl, ask, things, g.sem + i, search, vote);
            if (ask) z = _mm512_load_si512(zl);
        }
        _mm512_storeu_si512(g.inst + i, z);
        _mm512_storeu_ps(g.pan + i, _mm512_mul_ps(_mm512_loadu_ps(g.score + i), _mm512_i32gather_ps(z, g.centre_score, 4)));
    }
    return done;
}

/// groupRunAvx512 in 8 lanes, for CPUs without AVX-512 (the same operations). Returns the
/// pixels done (a multiple of 8).
template <class Search, class Vote>
PNDT_AVX2 size_t groupRunAvx2(const GroupingView& g, size_t i, size_t n, size_t x, size_t W, uint32_t y,
                              Search&& search, Vote&& vote)
{
    const __m256 iota = _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i several = _mm256_set1_epi32(int32_t(kSeveral));
    size_t done = 0;
    for (; i + 8 <= n && x + 8 <= W; i += 8, x += 8, done += 8)
    {
        __m256i thing = _mm256_setzero_si256();
        if (g.any_centre)
        {
            const __m256i am = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(g.am + (i - g.b0)));
            thing = _mm256_cmpgt_epi32(_mm256_i32gather_epi32(g.is_thing, am, 4), _mm256_setzero_si256());
        }
        const unsigned things = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(thing)));
        __m256i z = _mm256_setzero_si256();
        if (things)
        {
            __m256 sdx = _mm256_mul_ps(_mm256_set1_ps(g.scale), _mm256_loadu_ps(g.dx + i));
            __m256 sdy = _mm256_mul_ps(_mm256_set1_ps(g.scale), _mm256_loadu_ps(g.dy + i));
            asm("" : "+x"(sdx), "+x"(sdy));  // as the scalar code: round the product, then add
            const __m256 vx = _mm256_add_ps(_mm256_add_ps(_mm256_set1_ps(float(x)), iota), sdx);
            const __m256 vy = _mm256_add_ps(_mm256_set1_ps(float(y)), sdy);
            const __m256 gx = _mm256_mul_ps(_mm256_sub_ps(vx, _mm256_set1_ps(g.grid_x0)), _mm256_set1_ps(g.inv_cell));
            const __m256 gy = _mm256_mul_ps(_mm256_sub_ps(vy, _mm256_set1_ps(g.grid_y0)), _mm256_set1_ps(g.inv_cell));
            const __m256 zero = _mm256_setzero_ps();
            const __m256 in = _mm256_and_ps(
                _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(gx, zero, _CMP_GE_OQ),
                                            _mm256_cmp_ps(gx, _mm256_set1_ps(g.grid_w), _CMP_LT_OQ)),
                              _mm256_and_ps(_mm256_cmp_ps(gy, zero, _CMP_GE_OQ),
                                            _mm256_cmp_ps(gy, _mm256_set1_ps(g.grid_h), _CMP_LT_OQ))),
                _mm256_castsi256_ps(thing));
            const __m256i cell = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_cvttps_epi32(gy), _mm256_set1_epi32(g.grid_cols)),
                                                  _mm256_cvttps_epi32(gx));
            z = _mm256_mask_i32gather_epi32(several, reinterpret_cast<const int*>(g.grid_single), cell,
                                            _mm256_castps_si256(in), 4);
            z = _mm256_and_si256(z, thing);
            const unsigned ask =
                unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(z, several)))) & things;
            alignas(32) uint32_t zl[8];
            alignas(32) float vxl[8], vyl[8];
            _mm256_store_si256(reinterpret_cast<__m256i*>(zl), z);
            if (ask)
            {
                _mm256_store_ps(vxl, vx);
                _mm256_store_ps(vyl, vy);
            }
            searchAndVoteLanes<8>(zl, vxl, vyl, ask, things, g.sem + i, search, vote);
            if (ask) z = _mm256_load_si256(reinterpret_cast<const __m256i*>(zl));
        }
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(g.inst + i), z);
        _mm256_storeu_ps(g.pan + i, _mm256_mul_ps(_mm256_loadu_ps(g.score + i), _mm256_i32gather_ps(g.centre_score, z, 4)));
    }
    return done;
}

bool cpuHasAvx512()
{
    static const bool yes = __builtin_cpu_supports("avx512f") && cpuHasAvx2();
    return yes;
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#endif

}  // namespace

void PanopticPostprocessor::run(const PanopticTensors& t, PanopticFrame& out)
{
    if (t.width <= 0 || t.height <= 0 || !t.semantic)
        throw InputError(fmt::format("postprocess: empty semantic output ({}x{})", t.width, t.height));
    if (t.classes != int(channel_to_class_.size()))
        throw InputError(fmt::format("postprocess: the semantic output has {} channels but the model description "
                                     "names {} classes",
                                     t.classes, channel_to_class_.size()));
    if (t.center && !t.offset) throw InputError("postprocess: a centre heatmap needs an offset output");
    timing_ = {};
    const bool instances = t.center != nullptr;
    const int W = t.width, H = t.height;
    const size_t N = size_t(W) * H;
    double t0 = threadMs();
    if (instances)
    {
        findCenters(t);
        buildCentreGrid(W, H);
        votes_.assign((centers_.size() + 1) * classes_.size(), 0);  // row 0: pixels of no instance
        timing_.centres_ms = threadMs() - t0;
        t0 = threadMs();
    }
    else
        centers_.clear();

    // Outputs written in place; resized (which fills) only when the size changes.
    if (!out.semantic.sameSize(W, H)) out.semantic.resize(W, H);
    if (!out.semantic_score.sameSize(W, H)) out.semantic_score.resize(W, H);
    if (instances)
    {
        if (!out.instance.sameSize(W, H)) out.instance.resize(W, H);
        if (!out.panoptic_score.sameSize(W, H)) out.panoptic_score.resize(W, H);
    }
    else
    {
        out.instance = {};
        out.panoptic_score = {};
    }
    const int C = t.classes;
    const bool logits = options_.semantic_is_logit;
    const float skip = skipMargin(options_.score_tolerance, C);
    const size_t blocks = (N + kBlock - 1) / kBlock;
    block_has_instance_.assign(blocks, 0);
    const float inf = std::numeric_limits<float>::infinity();
    int skipped_last = 1;
    float* mx = scratch(max_logit_, kBlock, t.semantic, 1024);
    float* sum = scratch(exp_sum_, kBlock, t.semantic, 2048);
    int32_t* am = scratch(argmax_, kBlock, t.semantic, 3072);
    for (size_t b = 0; b < blocks; ++b)
    {
        const size_t b0 = b * kBlock, n = std::min(kBlock, N - b0);
        float* score = out.semantic_score.data.data() + b0;
        uint16_t* sem = out.semantic.data.data() + b0;
        bool finite;
        bool fused = false;  // max and softmax passes done together
#if PNDT_HAVE_AVX2_KERNEL
        using Kernel = PostprocessOptions::Kernel;
        const bool avx512 = options_.kernel == Kernel::Best && n % kSubBlock == 0 && cpuHasAvx512();
        const bool avx2 = options_.kernel != Kernel::Scalar && n % 8 == 0 && cpuHasAvx2();
        if (avx512)
        {
            finite = blockPixelsAvx512(t.semantic, N, C, b0, n, logits, skip, skipped_last, mx, am, channel_class_.data(),
                                       sem, score);
            fused = true;
        }
        else if (avx2 && n % kSubBlock == 0)
        {
            finite = blockPixelsAvx2(t.semantic, N, C, b0, n, logits, skip, skipped_last, mx, am, channel_class_.data(),
                                     sem, score);
            fused = true;
        }
        else if (avx2)  // a last block of a whole number of 8-pixel vectors, not of sub-blocks
            finite = blockMaxAvx2(t.semantic, N, C, b0, n, mx, am);
        else
#endif
            finite = blockMaxScalar(t.semantic, N, C, b0, n, mx, am);
        if (finite && logits && !fused)
        {
            for (size_t s0 = 0; s0 < n; s0 += kSubBlock)
            {
                const size_t m = std::min(kSubBlock, n - s0);
                // Where the last sub-block could leave no class out (noise), only every 4th one
                // tests the classes: the test costs a pass over the sub-block.
                const float sub_skip = skipped_last > 0 || (s0 / kSubBlock) % 4 == 0 ? skip : inf;
#if PNDT_HAVE_AVX2_KERNEL
                if (avx2)
                    skipped_last = blockSoftmaxAvx2(t.semantic, N, C, b0 + s0, m, mx + s0, sub_skip, sum + s0);
                else
#endif
                    skipped_last = blockSoftmaxScalar(t.semantic, N, C, b0 + s0, m, mx + s0, sub_skip, sum + s0);
            }
            for (size_t i = 0; i < n; ++i) score[i] = 1.f / sum[i];
        }
        else if (!finite)
        {
            // A NaN or infinite logit: every channel, as the definition reads (and its errors).
            blockArgmax(t.semantic, N, C, b0, n, mx, am);
            if (logits) blockSoftmaxScore(t.semantic, N, C, b0, n, mx, sum, score);
            for (size_t i = 0; i < n; ++i)
                if (!std::isfinite(mx[i]) || (logits && !std::isfinite(score[i])))
                    throw InputError(fmt::format("postprocess: non-finite semantic output at pixel ({}, {})",
                                                 (b0 + i) % size_t(W), (b0 + i) / size_t(W)));
        }
        if (!logits)
            for (size_t i = 0; i < n; ++i) score[i] = std::clamp(mx[i], 0.f, 1.f);
        if (!(fused && finite))
            for (size_t i = 0; i < n; ++i) sem[i] = channel_to_class_[size_t(am[i])];
        if (instances) groupBlock(t, b0, n, am, out);
    }
    timing_.pixels_ms = threadMs() - t0;
    if (!instances) return;
    t0 = threadMs();

    // Eq. 1: a thing pixel of instance z takes z's majority thing class (ties: smaller id).
    const size_t CL = classes_.size(), K = centers_.size();
    majority_.assign(K, 0);
    for (size_t k = 0; k < K; ++k)
    {
        const uint32_t* v = &votes_[(k + 1) * CL];
        uint16_t best = 0;
        for (size_t c = 1; c < CL; ++c)
            if (v[c] > v[best]) best = uint16_t(c);
        majority_[k] = best;
    }
    for (size_t b = 0; b < blocks; ++b)
    {
        if (!block_has_instance_[b]) continue;
        const size_t b0 = b * kBlock, n = std::min(kBlock, N - b0);
        const uint32_t* inst = out.instance.data.data() + b0;
        uint16_t* sem = out.semantic.data.data() + b0;
        for (size_t i = 0; i < n; ++i)
            if (inst[i]) sem[i] = majority_[inst[i] - 1];
    }
    timing_.merge_ms = threadMs() - t0;
}

void PanopticPostprocessor::findCenters(const PanopticTensors& t)
{
    const size_t N = size_t(t.width) * t.height;
    const float* prob = t.center;
    if (options_.center_is_logit)
    {
        center_prob_.resize(N);
        for (size_t i = 0; i < N; ++i) center_prob_[i] = 1.f / (1.f + std::exp(-t.center[i]));
        prob = center_prob_.data();
    }
    // A centre is the maximum of its nms_kernel window (max-pool == value) above the threshold.
    // Only pixels above the threshold can be centres, and each must be ≥ its 3×3 neighbours: on a
    // network's smooth heatmap a handful of windows are checked. A heatmap with many local maxima
    // above the threshold (noise) takes the max filter instead; both give the same centres.
    const int W = t.width, H = t.height, r = options_.nms_kernel / 2;
    const float thr = options_.center_threshold;
    const size_t budget = 4 * N / size_t(options_.nms_kernel * options_.nms_kernel) + 64;
    size_t checks = 0;
    centers_.clear();
    const auto windowMax = [&](int x, int y, int rx, float v) {
        for (int yy = std::max(0, y - rx); yy <= std::min(H - 1, y + rx); ++yy)
        {
            const float* row = prob + size_t(yy) * W;
            for (int xx = std::max(0, x - rx); xx <= std::min(W - 1, x + rx); ++xx)
                if (!(v >= row[xx])) return false;
        }
        return true;
    };
    bool sparse = true;
    for (int y = 0; y < H && sparse; ++y)
    {
        const float* row = prob + size_t(y) * W;
        for (int x0 = 0; x0 < W && sparse; x0 += 64)
        {
            const int x1 = std::min(W, x0 + 64);
            bool any = false;
            for (int x = x0; x < x1; ++x) any |= row[x] > thr;
            if (!any) continue;
            for (int x = x0; x < x1; ++x)
            {
                const float v = row[x];
                if (!(v > thr) || (r > 0 && !windowMax(x, y, 1, v))) continue;
                if (++checks > budget)
                {
                    sparse = false;
                    break;
                }
                if (windowMax(x, y, r, v)) centers_.push_back({x, y, std::min(v, 1.f)});
            }
        }
    }
    if (!sparse)
    {
        center_max_.resize(N);
        const cv::Mat in(H, W, CV_32F, const_cast<float*>(prob));
        cv::Mat pooled(H, W, CV_32F, center_max_.data());
        cv::dilate(in, pooled, cv::getStructuringElement(cv::MORPH_RECT, {options_.nms_kernel, options_.nms_kernel}),
                   {-1, -1}, 1, cv::BORDER_CONSTANT, cv::Scalar(-std::numeric_limits<float>::infinity()));
        centers_.clear();
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
            {
                const size_t i = size_t(y) * W + x;
                const float v = prob[i];
                if (v > thr && v >= center_max_[i]) centers_.push_back({x, y, std::min(v, 1.f)});
            }
    }
    // Highest first; ties in raster order (stable), so equal plateaus give one id order.
    std::stable_sort(centers_.begin(), centers_.end(),
                     [](const InstanceCenter& a, const InstanceCenter& b) { return a.score > b.score; });
    if (int(centers_.size()) > options_.top_k) centers_.resize(size_t(options_.top_k));
    centre_x_.resize(centers_.size());
    centre_y_.resize(centers_.size());
    for (size_t k = 0; k < centers_.size(); ++k)
    {
        centre_x_[k] = float(centers_[k].x);
        centre_y_[k] = float(centers_[k].y);
    }
}

void PanopticPostprocessor::buildCentreGrid(int width, int height)
{
    // Cells over the image; votes outside it are compared with every centre. A centre is listed
    // in a cell if its smallest distance to the cell (grown by a pixel against rounding) is within
    // the largest distance of the centre nearest to the whole cell, plus slack: no centre that
    // can be the nearest (float distances, ties included) to a vote in the cell is left out.
    grid_x0_ = 0.f;
    grid_y0_ = 0.f;
    grid_w_ = (width + kGridCell - 1) / kGridCell;
    grid_h_ = (height + kGridCell - 1) / kGridCell;
    grid_start_.assign(size_t(grid_w_) * grid_h_ + 1, 0);
    grid_single_.assign(size_t(grid_w_) * grid_h_, kSeveral);
    grid_ids_.clear();
    const size_t K = centers_.size();
    std::vector<double>& mind = scratch_d_;
    mind.resize(K);
    for (int gy = 0; gy < grid_h_; ++gy)
        for (int gx = 0; gx < grid_w_; ++gx)
        {
            const double x0 = grid_x0_ + gx * kGridCell - 1.0, x1 = grid_x0_ + (gx + 1) * kGridCell + 1.0;
            const double y0 = grid_y0_ + gy * kGridCell - 1.0, y1 = grid_y0_ + (gy + 1) * kGridCell + 1.0;
            double best_far = std::numeric_limits<double>::infinity();
            for (size_t k = 0; k < K; ++k)
            {
                const double cx = centre_x_[k], cy = centre_y_[k];
                const double nx = std::max({x0 - cx, 0.0, cx - x1}), ny = std::max({y0 - cy, 0.0, cy - y1});
                const double fx = std::max(std::abs(x0 - cx), std::abs(x1 - cx));
                const double fy = std::max(std::abs(y0 - cy), std::abs(y1 - cy));
                mind[k] = nx * nx + ny * ny;
                best_far = std::min(best_far, fx * fx + fy * fy);
            }
            const double limit = best_far * (1 + 1e-4) + 1.0;
            const size_t first = grid_ids_.size(), cell = size_t(gy) * grid_w_ + gx;
            for (size_t k = 0; k < K; ++k)
                if (mind[k] <= limit) grid_ids_.push_back(int32_t(k));
            grid_start_[cell + 1] = int32_t(grid_ids_.size());
            grid_single_[cell] = grid_ids_.size() == first + 1 ? uint32_t(grid_ids_[first]) + 1 : kSeveral;
        }
    centre_score_.assign(K + 1, 0.f);  // [0]: no instance
    for (size_t k = 0; k < K; ++k) centre_score_[k + 1] = centers_[k].score;
}

uint32_t PanopticPostprocessor::nearestCentre(float x, float y) const
{
    const float* cx = centre_x_.data();
    const float* cy = centre_y_.data();
    const float gx = (x - grid_x0_) * (1.f / kGridCell), gy = (y - grid_y0_) * (1.f / kGridCell);
    size_t k0 = 0, k1 = centers_.size();
    const int32_t* ids = nullptr;
    if (gx >= 0.f && gx < float(grid_w_) && gy >= 0.f && gy < float(grid_h_))  // false for NaN
    {
        const size_t cell = size_t(gy) * size_t(grid_w_) + size_t(gx);
        k0 = size_t(grid_start_[cell]);
        k1 = size_t(grid_start_[cell + 1]);
        ids = grid_ids_.data();
        if (k1 - k0 == 1) return uint32_t(ids[k0]) + 1;
    }
    // The nearest (strict <: ties keep the earlier centre); NaN votes join none.
    float best_d = std::numeric_limits<float>::infinity();
    uint32_t best = 0;
    for (size_t j = k0; j < k1; ++j)
    {
        const size_t k = ids ? size_t(ids[j]) : j;
        const float ex = x - cx[k], ey = y - cy[k];
        const float d = ex * ex + ey * ey;
        if (d < best_d)
        {
            best_d = d;
            best = uint32_t(k) + 1;
        }
    }
    return best;
}

void PanopticPostprocessor::groupBlock(const PanopticTensors& t, size_t b0, size_t n, const int32_t* am,
                                       PanopticFrame& out)
{
    const size_t N = size_t(t.width) * t.height, W = size_t(t.width);
    const float* dy = options_.offset_yx ? t.offset : t.offset + N;
    const float* dx = options_.offset_yx ? t.offset + N : t.offset;
    const float s = options_.offset_scale;
    const size_t CL = classes_.size();
    const float* score = out.semantic_score.data.data();
    const uint16_t* sem = out.semantic.data.data();
    uint32_t* inst = out.instance.data.data();
    float* pan = out.panoptic_score.data.data();
    const bool any_centre = !centers_.empty();
    const float inv = 1.f / kGridCell, gw = float(grid_w_), gh = float(grid_h_);
    uint32_t any = 0;
    // Each thing pixel votes for the point pixel + offset; it joins the centre nearest to it:
    // the grid cell's only candidate, else a search. (Stuff pixels branch away: on a network's
    // output they come in long runs, and they need neither their offsets nor a vote; with
    // AVX-512 such runs go 16 pixels a step, with AVX2 8.)
    size_t x = b0 % W, y = b0 / W;  // walked, not divided per pixel
#if PNDT_HAVE_AVX2_KERNEL
    using Kernel = PostprocessOptions::Kernel;
    const bool fast512 = options_.kernel == Kernel::Best && W >= 16 && cpuHasAvx512();
    const bool fast2 = !fast512 && options_.kernel != Kernel::Scalar && W >= 8 && cpuHasAvx2();
    GroupingView view{};
    if (fast512 || fast2)
    {
        view = {am, b0, channel_is_thing_.data(), any_centre, dx, dy, s, grid_x0_, grid_y0_, inv, gw, gh, grid_w_,
                grid_single_.data(), sem, score, centre_score_.data(), inst, pan};
    }
    const auto search = [this](float vx, float vy) { return nearestCentre(vx, vy); };
    const auto vote = [&](uint32_t z, uint16_t c) {
        ++votes_[z * CL + c];
        any |= z;
    };
#endif
    for (size_t i = 0; i < n; ++i)
    {
        const size_t j = b0 + i;
#if PNDT_HAVE_AVX2_KERNEL
        if ((fast512 && j % 16 == 0) || (fast2 && j % 8 == 0))
        {
            const size_t done = fast512 ? groupRunAvx512(view, j, b0 + n, x, W, uint32_t(y), search, vote)
                                        : groupRunAvx2(view, j, b0 + n, x, W, uint32_t(y), search, vote);
            if (done)
            {
                i += done - 1;  // the loop's ++i
                for (x += done; x >= W; x -= W) ++y;
                continue;
            }
        }
#endif
        uint32_t z = 0;
        if (any_centre && channel_is_thing_[size_t(am[i])])
        {
            const float vx = float(x) + s * dx[j], vy = float(y) + s * dy[j];
            const float gx = (vx - grid_x0_) * inv, gy = (vy - grid_y0_) * inv;
            const bool in = gx >= 0.f && gx < gw && gy >= 0.f && gy < gh;  // false for NaN
            z = in ? grid_single_[size_t(gy) * size_t(grid_w_) + size_t(gx)] : kSeveral;
            if (z == kSeveral) z = nearestCentre(vx, vy);
            ++votes_[z * CL + sem[j]];
            any |= z;
        }
        inst[j] = z;
        pan[j] = score[j] * centre_score_[z];
        if (++x == W)
        {
            x = 0;
            ++y;
        }
    }
    block_has_instance_[b0 / kBlock] = any != 0;
}

namespace
{
/// Nearest-neighbour resampling of one image: target pixel (x, y) takes source pixel
/// (floor((x + 0.5) W / width), floor((y + 0.5) H / height)), clamped. The source column
/// is stepped with integers (the same floor as the division); a target row whose source
/// row is the previous one's is a copy of it (upsampling: most rows).
template <typename T>
void resampleNearest(const Image<T>& in, int width, int height, Image<T>& out)
{
    const int W = in.width, H = in.height;
    out.reshape(width, height);  // every pixel is written
    int previous_sy = -1;
    for (int y = 0; y < height; ++y)
    {
        T* row = out.data.data() + size_t(y) * size_t(width);
        const int sy = std::min(H - 1, int((int64_t(2 * y + 1) * H) / (2 * int64_t(height))));
        if (sy == previous_sy)
        {
            std::copy(row - width, row, row);
            continue;
        }
        previous_sy = sy;
        const T* src = in.data.data() + size_t(sy) * size_t(W);
        // sx = floor((2x + 1) W / (2 width)): numerator and remainder carried along.
        const int64_t den = 2 * int64_t(width);
        int64_t sx = int64_t(W) / den, rem = int64_t(W) % den;
        const int64_t step = 2 * int64_t(W), step_q = step / den, step_r = step % den;
        for (int x = 0; x < width; ++x)
        {
            row[x] = src[std::min<int64_t>(W - 1, sx)];
            sx += step_q;
            rem += step_r;
            if (rem >= den)
            {
                rem -= den;
                ++sx;
            }
        }
    }
}
}  // namespace

void resizeLabels(const PanopticFrame& in, int width, int height, PanopticFrame& out)
{
    if (width <= 0 || height <= 0) throw InputError(fmt::format("resizeLabels: bad size {}x{}", width, height));
    if (in.semantic.empty() || in.semantic_score.size() != in.semantic.size() ||
        (in.hasInstances() && (in.instance.size() != in.semantic.size() || in.panoptic_score.size() != in.semantic.size())))
        throw InputError(fmt::format("resizeLabels: the labels to resize are empty or of different sizes"));
    resampleNearest(in.semantic, width, height, out.semantic);
    resampleNearest(in.semantic_score, width, height, out.semantic_score);
    if (in.hasInstances())
    {
        resampleNearest(in.instance, width, height, out.instance);
        resampleNearest(in.panoptic_score, width, height, out.panoptic_score);
    }
    else
    {
        out.instance = {};
        out.panoptic_score = {};
    }
}

}  // namespace pndt::seg
