// 2D: a map rendered into the frames of a nicr-layout sequence, against its GT label PNGs.
#pragma once

#include <pndt/eval/panoptic_evaluator.h>
#include <pndt/panoptic_map.h>

#include <string>

namespace pndt::evalapp
{
struct FrameScores
{
    eval::EvalResult result;
    size_t frames = 0;          ///< frames evaluated
    size_t skipped_no_pose = 0; ///< frames without a usable pose
    size_t skipped_no_gt = 0;   ///< frames without GT labels
};

/// Every `every`-th frame of sequence `sequence` under nicr split folder `split_dir`.
/// With `export_dir`, writes each rendered view as the TUI-NICR RGB8 panoptic PNG
/// (R = class, G << 8 | B = dense instance number) to <export_dir>/panoptic_2d/<frame>.png.
/// Throws InputError naming the folder when no frame could be evaluated.
FrameScores evaluateFrames(const PanopticMap& map, const std::string& split_dir, const std::string& sequence,
                           const eval::Benchmark& bench, int every, const std::string& export_dir = {});
}  // namespace pndt::evalapp
