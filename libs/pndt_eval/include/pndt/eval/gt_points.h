// Ground truth of a user's scene for 3D evaluation: the points of a PLY (a labelled GT
// cloud, or a mesh's vertices) and their labels, from the PLY's `label` property
// (sem << 16 | ins, the Hypersim protocol of anchors §1.5) or from a ScanNet benchmark
// text file (one label per line, line i = vertex i, sem * shift + ins).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace pndt::eval
{
struct GtPoints
{
    std::vector<Eigen::Vector3d> points;
    std::vector<uint32_t> labels;  ///< sem << 16 | ins per point; empty when not read
};

/// The vertices of a PLY (ascii or binary little-endian; the vertex element must come
/// first, as in nicr GT clouds and ScanNet meshes; other elements are ignored), with the
/// `label` property when `with_labels`. Throws InputError naming the file for a missing
/// file, a malformed or truncated header or body, a missing x/y/z or label property, or a
/// vertex count the file cannot hold (checked before allocating).
GtPoints readPlyPoints(const std::string& path, bool with_labels);

/// ScanNet-style labels (sem * shift + ins, shift 1000 in ScanNet's own files, 65536 in
/// the nicr-patched ones) as sem << 16 | ins. Throws InputError naming `source` and the
/// line for a class above 65535 or an instance >= shift.
std::vector<uint32_t> panopticFromShifted(const std::vector<uint32_t>& labels, uint32_t shift,
                                          const std::string& source);

}  // namespace pndt::eval
