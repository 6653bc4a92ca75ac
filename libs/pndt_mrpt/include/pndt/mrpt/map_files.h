// Files of the map (written atomically with pndt::io::writeFileAtomically): MRPT archives of serialised maps, PLY export.
#pragma once

#include <mrpt/serialization/CSerializable.h>
#include <pndt/io/atomic_file.h>
#include <pndt/mrpt/PanopticNDTMap.h>

#include <ostream>
#include <string>

namespace pndt
{
/// Serialises any MRPT object into a gzip archive at `path`, atomically.
void saveArchive(const mrpt::serialization::CSerializable& obj, const std::string& path);

/// Reads a map archive written by saveArchive(); throws std::runtime_error naming
/// the file for a missing, truncated or foreign file.
PanopticNDTMap::Ptr loadMapArchive(const std::string& path);

/// Occupied voxels as a binary PLY: x y z (NDT mean), red green blue (panoptic
/// colours), semantic, instance (propagated map id), label = semantic<<16 | n with n the
/// instance's dense number (InstanceNumbering: ids after a short-term hand-over exceed
/// 16 bits), occupancy probability. Written atomically.
void writePly(const PanopticNDTMap& map, const std::string& path, ColorMode colors = ColorMode::Panoptic);

}  // namespace pndt
