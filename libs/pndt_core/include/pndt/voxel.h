// What the map stores per voxel (design §2), split by how often it is needed:
// - every mapped voxel has a Voxel: occupancy and a link, 8 bytes;
// - only voxels that were ever hit (an endpoint fell in them) have a
//   SurfaceRecord: the NDT shape and the link to the labels, 44 bytes;
// - only surface voxels that got a semantic update have a LabelRecord, and only
//   those that got an instance update an InstanceRecord.
// Free-space voxels, the large majority, thus cost 8 bytes plus their place in
// the brick index (voxel_store.h).
#pragma once

#include <pndt/build_config.h>  // PNDT_QUANTISED_HISTOGRAMS as the library was built
#include <pndt/gaussian.h>
#include <pndt/sparse_histogram.h>

#include <cstdint>
#include <limits>

namespace pndt
{
constexpr uint32_t kNoRecord = std::numeric_limits<uint32_t>::max();
/// h^L's id for void (option void_bin): id 0 marks a histogram's free entries,
/// and a class set has at most 255 classes (ids 0..254), so 255 is free. It
/// counts as stuff and reads as void (semanticArgmax).
constexpr uint8_t kVoidBin = 255;

// Histogram weights: floats (exact, default) or 16-bit with a shared scale
// (CMake option PNDT_QUANTISED_HISTOGRAMS: 12 bytes less per label record, 28
// per instance record; accuracy in doc/results.md, memory in doc/benchmarks.md).
#if PNDT_QUANTISED_HISTOGRAMS
constexpr bool kQuantisedHistograms = true;
template <int Capacity>
using HistogramWeights = QuantisedWeights<Capacity>;
#else
constexpr bool kQuantisedHistograms = false;
template <int Capacity>
using HistogramWeights = FloatWeights<Capacity>;
#endif

struct Voxel
{
    float occ = 0;                 ///< occupancy log-odds, clamped
    uint32_t surface = kNoRecord;  ///< index into the SurfaceRecord pool (voxels ever hit)
};

/// NDT shape of a voxel that was hit at least once, and its labels.
struct SurfaceRecord
{
    NdtShape shape;
    uint32_t labels = kNoRecord;  ///< index into the LabelRecord pool
};

/// Semantic histogram h^L (sparse: a surface voxel sees few classes) and the
/// update counter n^L. Its sum and stuff part are derived from the entries
/// (instance_rules.h).
struct LabelRecord
{
    static constexpr int kSemanticCapacity = 8;
    SparseHistogram<uint8_t, kSemanticCapacity, HistogramWeights<kSemanticCapacity>> semantic;
    uint32_t n_l = 0;
    uint32_t instances = kNoRecord;  ///< index into the InstanceRecord pool
};

/// Sparse instance histogram h^Z: at most 16 (id, weight) entries, and its
/// update counter n^Z (here, not in the LabelRecord: only voxels with an
/// instance histogram ever count instance updates).
using InstanceHistogram = SparseHistogram<uint32_t, 16, HistogramWeights<16>>;
struct InstanceRecord
{
    InstanceHistogram hist;
    uint32_t n_z = 0;
};

// Most of a map's memory (doc/benchmarks.md): keep an eye on padding.
static_assert(sizeof(SurfaceRecord) == 44);
static_assert(kQuantisedHistograms ? sizeof(LabelRecord) == 36 && sizeof(InstanceRecord) == 104
                                   : sizeof(LabelRecord) == 48 && sizeof(InstanceRecord) == 132);

/// Propagated panoptic label <semantic, instance> (instance 0 = none).
struct PanopticLabel
{
    uint16_t semantic = 0;
    uint32_t instance = 0;
    bool operator==(const PanopticLabel& o) const { return semantic == o.semantic && instance == o.instance; }
};

}  // namespace pndt
