// The inner loop of vtou (instance matching): one image row of a thing voxel's
// footprint, its pixels that pass the depth test cut into runs of one predicted
// instance. Most pixels continue the run before them: the AVX2 and AVX-512
// versions test 8 / 16 pixels a step and visit only the pixels where the run
// changes. Every version gives the same spans as the scalar one.
#pragma once

#include <cstdint>

#include "mask_footprint.h"

namespace pndt
{
/// The depth test as one float interval: for every float d (NaN and infinities
/// included), lo <= d <= hi exactly when |double(d) - z0| <= tolerance. The
/// double difference rounds monotonically in d, so the passing floats are an
/// interval; its ends are found by stepping from the rounded bounds.
struct DepthWindow
{
    float lo = 1.f, hi = 0.f;  ///< empty by default
};
DepthWindow depthWindow(double z0, double tolerance);

/// Pixels [c0, c1] of one row (`predicted` and `depth` point at the row's first
/// pixel, `row` is that pixel's index): appends a span per run of passing pixels
/// of one predicted index (kUnmappedPixel and failing pixels end runs), the
/// index translated by `to_frame` when >= 0. Returns the spans appended.
using MaskRowFn = uint32_t (*)(const int32_t* predicted, const float* depth, int c0, int c1, DepthWindow w,
                               uint32_t row, const int32_t* to_frame, MaskSpan* out);
uint32_t maskRowScalar(const int32_t* predicted, const float* depth, int c0, int c1, DepthWindow w, uint32_t row,
                       const int32_t* to_frame, MaskSpan* out);
MaskRowFn maskRowAvx2();    ///< nullptr without AVX2
MaskRowFn maskRowAvx512();  ///< nullptr without AVX-512 F
/// The fastest version this CPU runs within simdCap().
MaskRowFn bestMaskRow();

/// Every row of a footprint: each row's chord (footprintRow) through the row
/// kernel, at pixel index r * W; `row_remap[r]` is row r's `to_frame`. The
/// same spans as a loop over footprintRow and the row kernel.
using MaskFootprintFn = uint32_t (*)(const MaskFootprint& fp, double k2, const int32_t* predicted, const float* depth,
                                     int W, DepthWindow w, const int32_t* const* row_remap, MaskSpan* out);
uint32_t maskFootprintScalar(const MaskFootprint& fp, double k2, const int32_t* predicted, const float* depth, int W,
                             DepthWindow w, const int32_t* const* row_remap, MaskSpan* out);
MaskFootprintFn maskFootprintAvx2();    ///< nullptr without AVX2
MaskFootprintFn maskFootprintAvx512();  ///< nullptr without AVX-512 F
MaskFootprintFn bestMaskFootprint();

}  // namespace pndt
