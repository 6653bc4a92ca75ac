// The exposed faces of a map's occupied voxels as one triangle set: a face is drawn only
// where the neighbour across it is not occupied, so surfaces look solid (no inner faces,
// no gaps), coloured like the panoptic view and shaded by face direction. Ceiling voxels
// are left out so the room can be seen from above.
#pragma once

#include <mrpt/opengl/CSetOfTriangles.h>
#include <pndt/panoptic_map.h>

namespace pndt::app
{
mrpt::opengl::CSetOfTriangles::Ptr exposedFaceMesh(const PanopticMap& map);
/// Faces the mesh of `map` has (2 triangles each), for tests.
size_t exposedFaceCount(const PanopticMap& map);
}  // namespace pndt::app
