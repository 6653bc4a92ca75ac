// The hand-made scene of the map evaluation tests: a wall 2.05 m ahead (a voxel centre
// plane at 10 cm), its left half wall (stuff), its right half one picture (a thing).
#pragma once

#include <pndt/frame.h>

namespace wall_scene
{
constexpr uint16_t kWall = 1, kFloor = 2, kPicture = 11;
constexpr float kDepth = 2.05f;

/// 64x48 camera at the origin looking along +z. Columns < 32 (x < 0 on the wall) are wall,
/// columns >= 32 (x > 0) picture instance 1; scores above every threshold.
inline pndt::PanopticFrame labelledWall()
{
    pndt::PanopticFrame f;
    f.K = {64, 48, 32.0, 32.0, 31.5, 23.5};
    f.depth.resize(64, 48, kDepth);
    f.semantic.resize(64, 48, kWall);
    f.semantic_score.resize(64, 48, 0.9f);
    f.instance.resize(64, 48, 0);
    f.panoptic_score.resize(64, 48, 0.f);
    for (int r = 0; r < 48; ++r)
        for (int c = 32; c < 64; ++c)
        {
            f.semantic.at(r, c) = kPicture;
            f.instance.at(r, c) = 1;
            f.panoptic_score.at(r, c) = 0.8f;
        }
    f.source = "TEST wall";
    return f;
}
}  // namespace wall_scene
