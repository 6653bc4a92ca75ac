// The benchmark's input: identical synthetic frames for every mapper.
#pragma once

#include <pndt/frame.h>

#include <string>
#include <vector>

namespace pndt::bench
{
struct BenchFrames
{
    std::vector<PanopticFrame> frames;  ///< depth + perfect labels, instance ids permuted per frame
    std::vector<Pose> poses;            ///< optical camera in the world
    std::vector<std::vector<Eigen::Vector3f>> world_points;  ///< valid depth pixels in the world
};

/// `n` frames of the synthetic room along a smooth orbit at `width`x`height`.
/// Perfect labels, or with `noise` > 0 segment-coherent errors (a segment takes
/// a wrong class, an instance splits in two, each with that probability per
/// frame) and per-pixel scores in [0.5, 1].
BenchFrames makeRoomFrames(int n, int width, int height, double max_range, double noise = 0.0);
/// `n` frames spread over a recording folder (Redwood or TUM layout, real depth
/// and poses), depth beyond `max_range` dropped, with synthetic labels: a 6x6 grid
/// of segments (wall, floor, 24 things with new ids every frame), `noise` as above.
/// Throws naming the folder if it cannot be read or has no posed frame.
BenchFrames makeRecordingFrames(const std::string& folder, int n, double max_range, double noise = 0.0);
}  // namespace pndt::bench
