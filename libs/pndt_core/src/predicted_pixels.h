// Each mapped pixel's predicted instance (its row band's local index) and each
// predicted instance's area and class, for one band of the image. Most pixels
// continue the previous pixel's instance (or are background or unmapped): an
// AVX-512 version settles 16 such pixels per step and leaves the pixels that
// start an instance to the scalar loop. Both give the same results.
#pragma once

#include <cstddef>
#include <cstdint>

#include "map_scratch.h"
#include "projection_kernels.h"

namespace pndt
{
/// Pixels [0, n) in whole blocks of 16 while none starts an instance other than
/// `id`: writes their predicted index (`local`, -1 for background, kUnmappedPixel)
/// and adds the pixels of `id` to `run`. Returns how many pixels it settled.
using ContinueInstanceFn = size_t (*)(const uint32_t* ids, const int32_t* slots, int32_t* predicted, size_t n,
                                      uint32_t id, int32_t local, uint64_t& run);
/// nullptr when the CPU (or the compiler) has no AVX-512 F.
ContinueInstanceFn continueInstanceAvx512();
ContinueInstanceFn continueInstanceAvx2();  ///< nullptr without AVX2
/// The fastest version this CPU runs within simdCap(); nullptr: no fast path.
ContinueInstanceFn bestContinueInstance();

/// Pixels [i0, i1) of the image into `pb` (cleared first): ids, areas (mapped
/// pixels), classes at the first pixel, and `predicted` per pixel. `sem` may be
/// nullptr (class 0). `fast` may be nullptr.
void assignPredicted(const uint32_t* ids, const uint16_t* sem, const int32_t* slots, int32_t* predicted, size_t i0,
                     size_t i1, PredictedBand& pb, ContinueInstanceFn fast);

}  // namespace pndt
