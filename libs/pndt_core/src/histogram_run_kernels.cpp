// AVX-512 and AVX2 block tests of the histogram pass (see histogram_run_kernels.h). Each
// lane repeats the scalar loop's tests: its class (class-0 pixels as void_id),
// its instance id (a split pixel's own id, else the decision of its predicted
// instance), and "update" as score > threshold.
#include "histogram_run_kernels.h"

#include "projection_kernels.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define PNDT_HAVE_X86_KERNELS 1
#endif

namespace pndt
{
#ifdef PNDT_HAVE_X86_KERNELS
namespace
{
/// A block's first `count` scores added to the runs one by one, in pixel order:
/// the scalar loop's float sums (every version shares this part).
[[gnu::always_inline]] inline void addInPixelOrder(const float* z_add, const float* l_add, uint32_t count, float& zw,
                                                   float& lw)
{
    for (uint32_t j = 0; j < count; ++j)
    {
        zw += z_add[j];
        lw += l_add[j];
    }
}

/// The block loop's weights and update counts into the caller's runs.
[[gnu::always_inline]] inline void keepSums(RunSums& sums, float zw, float lw, uint32_t nz, uint32_t nl)
{
    sums.z_weight = zw;
    sums.l_weight = lw;
    sums.z_updates += nz;
    sums.l_updates += nl;
}
}  // namespace

__attribute__((target("avx512f"))) static uint32_t continueRunsAvx512Impl(const RunBlockInputs& in, uint32_t i,
                                                                          uint32_t end, RunSums& sums)
{
    const __m512i zero = _mm512_setzero_si512();
    const __m512i run_l = _mm512_set1_epi32(sums.l), run_z = _mm512_set1_epi32(int32_t(sums.z)),
                  void_id = _mm512_set1_epi32(in.void_id), split_now = _mm512_set1_epi32(int32_t(in.split_now));
    const __m512 theta_l = _mm512_set1_ps(in.theta_l), theta_z = _mm512_set1_ps(in.theta_z);
    float zw = sums.z_weight, lw = sums.l_weight;
    uint32_t nz = 0, nl = 0;
    alignas(64) float z_add[16], l_add[16];
    for (; end - i >= 16; i += 16)
    {
        // (the masked form: GCC 12 warns about the unmasked one's undefined source)
        const __m512i cls =
            _mm512_maskz_cvtepu16_epi32(0xFFFF, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(in.semantic + i)));
        const __m512i L = _mm512_mask_mov_epi32(cls, _mm512_cmpeq_epi32_mask(cls, zero), void_id);
        const __m512 sl = _mm512_loadu_ps(in.semantic_score + i);
        const __mmask16 take_l = _mm512_cmpneq_epi32_mask(L, zero) & _mm512_cmp_ps_mask(sl, theta_l, _CMP_GT_OQ);
        __mmask16 good = ~(take_l & _mm512_cmpneq_epi32_mask(L, run_l));
        __mmask16 take_z = 0;
        __m512 sp = _mm512_setzero_ps();
        if (in.predicted)
        {
            const __m512i p = _mm512_loadu_si512(in.predicted + i);
            __m512i z = _mm512_mask_i32gather_epi32(zero, _mm512_cmpge_epi32_mask(p, zero), p, in.decision, 4);
            if (in.split_stamp)
            {
                const __mmask16 split = _mm512_cmpeq_epi32_mask(_mm512_loadu_si512(in.split_stamp + i), split_now);
                z = _mm512_mask_loadu_epi32(z, split, in.split_id + i);
            }
            sp = _mm512_loadu_ps(in.panoptic_score + i);
            take_z = _mm512_cmpneq_epi32_mask(z, zero) & _mm512_cmp_ps_mask(sp, theta_z, _CMP_GT_OQ);
            good &= ~(take_z & _mm512_cmpneq_epi32_mask(z, run_z));
        }
        _mm512_store_ps(z_add, _mm512_maskz_mov_ps(take_z, sp));
        _mm512_store_ps(l_add, _mm512_maskz_mov_ps(take_l, sl));
        const uint32_t count = good == 0xFFFF ? 16u : uint32_t(__builtin_ctz(~uint32_t(good)));
        addInPixelOrder(z_add, l_add, count, zw, lw);
        const uint32_t first = count == 16 ? 0xFFFFu : (1u << count) - 1u;
        nz += uint32_t(__builtin_popcount(take_z & first));
        nl += uint32_t(__builtin_popcount(take_l & first));
        if (count < 16)
        {
            i += count;
            break;
        }
    }
    keepSums(sums, zw, lw, nz, nl);
    return i;
}

// The same tests on eight lanes, for CPUs without AVX-512 (without the block
// test the pass went pixel by pixel there: the largest function of a 10 cm profile on a Zen 3).
__attribute__((target("avx2"))) static uint32_t continueRunsAvx2Impl(const RunBlockInputs& in, uint32_t i,
                                                                     uint32_t end, RunSums& sums)
{
    const __m256i zero = _mm256_setzero_si256(), minus_one = _mm256_set1_epi32(-1);
    const __m256i run_l = _mm256_set1_epi32(sums.l), run_z = _mm256_set1_epi32(int32_t(sums.z)),
                  void_id = _mm256_set1_epi32(in.void_id), split_now = _mm256_set1_epi32(int32_t(in.split_now));
    const __m256 theta_l = _mm256_set1_ps(in.theta_l), theta_z = _mm256_set1_ps(in.theta_z);
    float zw = sums.z_weight, lw = sums.l_weight;
    uint32_t nz = 0, nl = 0;
    alignas(32) float z_add[8], l_add[8];
    for (; end - i >= 8; i += 8)
    {
        const __m256i cls = _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in.semantic + i)));
        const __m256i L = _mm256_blendv_epi8(cls, void_id, _mm256_cmpeq_epi32(cls, zero));
        const __m256 sl = _mm256_loadu_ps(in.semantic_score + i);
        // take: L != 0 and score > theta (ordered: a NaN score is no update)
        const __m256i take_l = _mm256_andnot_si256(_mm256_cmpeq_epi32(L, zero),
                                                   _mm256_castps_si256(_mm256_cmp_ps(sl, theta_l, _CMP_GT_OQ)));
        __m256i bad = _mm256_andnot_si256(_mm256_cmpeq_epi32(L, run_l), take_l);
        __m256i take_z = zero;
        __m256 sp = _mm256_setzero_ps();
        if (in.predicted)
        {
            const __m256i p = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(in.predicted + i));
            const __m256i has = _mm256_cmpgt_epi32(p, minus_one);  // p >= 0
            __m256i z = _mm256_mask_i32gather_epi32(zero, reinterpret_cast<const int*>(in.decision), p, has, 4);
            if (in.split_stamp)
            {
                const __m256i split = _mm256_cmpeq_epi32(
                    _mm256_loadu_si256(reinterpret_cast<const __m256i*>(in.split_stamp + i)), split_now);
                z = _mm256_blendv_epi8(z, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(in.split_id + i)), split);
            }
            sp = _mm256_loadu_ps(in.panoptic_score + i);
            take_z = _mm256_andnot_si256(_mm256_cmpeq_epi32(z, zero),
                                         _mm256_castps_si256(_mm256_cmp_ps(sp, theta_z, _CMP_GT_OQ)));
            bad = _mm256_or_si256(bad, _mm256_andnot_si256(_mm256_cmpeq_epi32(z, run_z), take_z));
        }
        _mm256_store_ps(z_add, _mm256_and_ps(_mm256_castsi256_ps(take_z), sp));
        _mm256_store_ps(l_add, _mm256_and_ps(_mm256_castsi256_ps(take_l), sl));
        const uint32_t bad_bits = uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(bad)));
        const uint32_t count = bad_bits == 0 ? 8u : uint32_t(__builtin_ctz(bad_bits));
        addInPixelOrder(z_add, l_add, count, zw, lw);
        const uint32_t first = (1u << count) - 1u;
        nz += uint32_t(__builtin_popcount(uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(take_z))) & first));
        nl += uint32_t(__builtin_popcount(uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(take_l))) & first));
        if (count < 8)
        {
            i += count;
            break;
        }
    }
    keepSums(sums, zw, lw, nz, nl);
    return i;
}

ContinueRuns bestContinueRuns()
{
    __builtin_cpu_init();
    if (simdCap() == SimdCap::Avx512 && __builtin_cpu_supports("avx512f")) return {&continueRunsAvx512Impl, 16};
    if (simdCap() >= SimdCap::Avx2 && __builtin_cpu_supports("avx2")) return {&continueRunsAvx2Impl, 8};
    return {};
}
#else
ContinueRuns bestContinueRuns() { return {}; }
#endif

}  // namespace pndt
