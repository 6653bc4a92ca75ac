// The histogram pass's common case, 16 (AVX-512) or 8 (AVX2) pixels a step:
// pixels of one span (one voxel) whose class and instance either continue the
// current runs or are no update. The tests run on the lanes; the scores are
// then added one by one in pixel order, so the weights keep the bits of the
// pixel-by-pixel loop (float sums depend on their order).
#pragma once

#include <cstdint>

namespace pndt
{
/// The per-pixel arrays of a one-band histogram pass (pixel i indexes each).
struct RunBlockInputs
{
    const uint16_t* semantic = nullptr;  ///< class
    const float* semantic_score = nullptr;
    const int32_t* predicted = nullptr;     ///< predicted index, < 0 none; nullptr: no instances
    const uint32_t* decision = nullptr;     ///< map id per predicted index
    const uint32_t* split_stamp = nullptr;  ///< nullptr: no split pixels this frame
    const uint32_t* split_id = nullptr;
    uint32_t split_now = 0;
    const float* panoptic_score = nullptr;
    float theta_l = 0, theta_z = 0;
    uint16_t void_id = 0;  ///< class of class-0 pixels (0: they are no update)
};

/// The current runs: their ids (0: none) and sums.
struct RunSums
{
    uint32_t z = 0;                    ///< the instance run's id
    uint16_t l = 0;                    ///< the semantic run's class
    float z_weight = 0, l_weight = 0;  ///< the runs' weights (scores added in pixel order)
    uint32_t z_updates = 0, l_updates = 0;
};

/// Pixels [i, end) of one span, a block a step while a block is left: adds the pixels
/// that continue the runs to `sums` and returns the first that does not (or
/// where less than a block is left); the caller takes the rest the scalar way.
using ContinueRunsFn = uint32_t (*)(const RunBlockInputs& in, uint32_t i, uint32_t end, RunSums& sums);
/// A block test and its block: spans of `block` pixels or more start with it.
struct ContinueRuns
{
    ContinueRunsFn fn = nullptr;  ///< nullptr: the pass goes pixel by pixel
    uint32_t block = 0;
};
/// AVX-512 F (16 pixels a step) or AVX2 (8), within simdCap(); none below.
ContinueRuns bestContinueRuns();

}  // namespace pndt
