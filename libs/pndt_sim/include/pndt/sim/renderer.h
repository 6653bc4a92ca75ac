// Exact per-pixel ray-cast renderer: depth + ground-truth semantic + instance.
#pragma once

#include <cstdint>

#include "pndt/frame.h"
#include "pndt/sim/scene.h"
#include "pndt/types.h"

namespace pndt::sim
{
struct RenderedFrame
{
    Image<float> depth;         ///< metres along the optical z axis; 0 where no hit
    Image<uint16_t> semantic;   ///< NYUv2-40 class id; 0 where no hit
    Image<uint32_t> instance;   ///< instance id (0 for walls/floor/ceiling and no hit)
};

/// Renders `scene` seen by a pinhole camera (optical frame, pose T_world_cam) into
/// `out`, sized K.width x K.height. Each pixel centre's ray is intersected exactly
/// with every primitive (oriented-box slab test, closed cylinder) and the room; the
/// nearest hit wins (ties: earlier primitive, primitives before the room). Hits whose
/// depth exceeds `max_range` (optical z, not Euclidean range) give depth 0 and labels 0.
/// Per pixel the result equals castRay(scene, eye, pixelRayDirection(...), max_range).
/// `out`'s buffers are reused when the size is unchanged. Single-threaded, deterministic.
/// Throws InputError if K is not valid.
void render(const Scene& scene, const Pose& T_world_cam, const CameraIntrinsics& K,
            RenderedFrame& out, double max_range = 10.0);

/// What a perfect camera and segmentation give at T_world_cam: render()'s depth and
/// labels as a map frame, every semantic and panoptic score `score` (examples, tests).
PanopticFrame renderPanopticFrame(const Scene& scene, const Pose& T_world_cam, const CameraIntrinsics& K,
                                  float score = 0.9f);

}  // namespace pndt::sim
