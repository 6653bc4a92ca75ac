#include "predicted_pixels.h"

#include <algorithm>

#if defined(__x86_64__) || defined(_M_X64)
#include <immintrin.h>
#define PNDT_X86 1
#endif

namespace pndt
{
void assignPredicted(const uint32_t* ids, const uint16_t* sem, const int32_t* slots, int32_t* predicted, size_t i0,
                     size_t i1, PredictedBand& pb, ContinueInstanceFn fast)
{
    pb.index.clear();
    pb.ids.clear();
    pb.area.clear();
    pb.cls.clear();
    uint32_t last_id = 0;
    int32_t last_local = -1;
    uint64_t run = 0;  // pixels of last_local not yet counted
    for (size_t i = i0; i < i1;)
    {
        if (fast)
        {
            i += fast(ids + i, slots + i, predicted + i, i1 - i, last_id, last_local, run);
            if (i >= i1) break;
        }
        // The pixels the fast path left: up to one block, at least one pixel.
        for (const size_t e = std::min(i1, i + 16); i < e; ++i)
        {
            const uint32_t id = ids[i];
            if (id == 0 || slots[i] < 0)
            {
                predicted[i] = slots[i] < 0 ? kUnmappedPixel : -1;
                continue;
            }
            if (id != last_id)  // runs of one instance along a row
            {
                if (last_local >= 0) pb.area[size_t(last_local)] += run;
                run = 0;
                const auto [it, inserted] = pb.index.try_emplace(id, uint32_t(pb.ids.size()));
                if (inserted)
                {
                    pb.ids.push_back(id);
                    pb.area.push_back(0);
                    pb.cls.push_back(sem ? sem[i] : 0);  // Eq. 1: one class per predicted instance
                }
                last_id = id;
                last_local = int32_t(it->second);
            }
            predicted[i] = last_local;
            ++run;
        }
    }
    if (last_local >= 0) pb.area[size_t(last_local)] += run;
}

#ifdef PNDT_X86
namespace
{
__attribute__((target("avx512f"))) size_t continueInstanceAvx512Impl(const uint32_t* ids, const int32_t* slots,
                                                                     int32_t* predicted, size_t n, uint32_t id,
                                                                     int32_t local, uint64_t& run)
{
    const __m512i zero = _mm512_setzero_si512(), vid = _mm512_set1_epi32(int32_t(id)),
                  vlocal = _mm512_set1_epi32(local), none = _mm512_set1_epi32(-1),
                  unmapped = _mm512_set1_epi32(kUnmappedPixel);
    size_t k = 0;
    uint64_t added = 0;
    for (; k + 16 <= n; k += 16)
    {
        const __m512i z = _mm512_loadu_si512(ids + k), sl = _mm512_loadu_si512(slots + k);
        const __mmask16 mapped = _mm512_cmpge_epi32_mask(sl, zero);
        const __mmask16 instance = mapped & _mm512_cmpneq_epi32_mask(z, zero);
        const __mmask16 same = _mm512_cmpeq_epi32_mask(z, vid);
        if (instance & ~same) break;  // an instance other than id starts in this block
        __m512i out = _mm512_mask_mov_epi32(unmapped, mapped, none);
        out = _mm512_mask_mov_epi32(out, instance, vlocal);
        _mm512_storeu_si512(predicted + k, out);
        added += uint64_t(__builtin_popcount(instance));
    }
    run += added;
    return k;
}

// The same with eight pixels a block.
__attribute__((target("avx2"))) size_t continueInstanceAvx2Impl(const uint32_t* ids, const int32_t* slots,
                                                                 int32_t* predicted, size_t n, uint32_t id,
                                                                 int32_t local, uint64_t& run)
{
    const __m256i zero = _mm256_setzero_si256(), vid = _mm256_set1_epi32(int32_t(id)),
                  vlocal = _mm256_set1_epi32(local), none = _mm256_set1_epi32(-1),
                  unmapped = _mm256_set1_epi32(kUnmappedPixel);
    size_t k = 0;
    uint64_t added = 0;
    for (; k + 8 <= n; k += 8)
    {
        const __m256i z = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ids + k)),
                      sl = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(slots + k));
        const __m256i mapped = _mm256_xor_si256(_mm256_cmpgt_epi32(zero, sl), none);  // slot >= 0
        const __m256i instance = _mm256_andnot_si256(_mm256_cmpeq_epi32(z, zero), mapped);
        const __m256i same = _mm256_cmpeq_epi32(z, vid);
        // An instance other than id starts in this block.
        if (_mm256_movemask_epi8(_mm256_andnot_si256(same, instance))) break;
        const __m256i out = _mm256_blendv_epi8(_mm256_blendv_epi8(unmapped, none, mapped), vlocal, instance);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(predicted + k), out);
        added += uint64_t(__builtin_popcount(unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(instance)))));
    }
    run += added;
    return k;
}
}  // namespace

ContinueInstanceFn continueInstanceAvx512()
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") ? &continueInstanceAvx512Impl : nullptr;
}
ContinueInstanceFn continueInstanceAvx2()
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") ? &continueInstanceAvx2Impl : nullptr;
}
#else
ContinueInstanceFn continueInstanceAvx512() { return nullptr; }
ContinueInstanceFn continueInstanceAvx2() { return nullptr; }
#endif

ContinueInstanceFn bestContinueInstance()
{
    const ContinueInstanceFn avx512 = simdCap() == SimdCap::Avx512 ? continueInstanceAvx512() : nullptr;
    return avx512 ? avx512 : simdCap() >= SimdCap::Avx2 ? continueInstanceAvx2() : nullptr;
}

}  // namespace pndt
