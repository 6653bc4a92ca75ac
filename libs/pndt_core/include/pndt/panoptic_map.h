// The panoptic occupancy NDT map (paper §III): integrate frames, query labels.
// Pure algorithm: no file I/O, no MRPT. Not thread-safe: one writer, and
// queries must not run concurrently with integrate(). integrate() itself may
// use several threads (MapOptions::threads); the result does not depend on
// their number.
#pragma once

#include <pndt/frame.h>
#include <pndt/map_options.h>
#include <pndt/record_pool.h>
#include <pndt/semantic_spill.h>
#include <pndt/voxel_store.h>
#include <tsl/robin_map.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace pndt
{
/// What one integrate() call did; counts and seconds per stage.
struct FrameStats
{
    uint64_t pixels = 0;
    uint64_t valid_pixels = 0;
    uint64_t skipped_invalid_depth = 0;  ///< NaN, inf, zero or negative
    uint64_t skipped_over_range = 0;
    uint64_t skipped_outside_grid = 0;
    uint64_t hit_voxels = 0;
    uint64_t rays = 0;
    uint64_t missed_voxels = 0;
    uint64_t predicted_instances = 0;
    uint64_t matched_instances = 0;
    uint64_t new_instances = 0;
    uint64_t ambiguous_instances = 0;
    uint64_t split_predictions = 0;      ///< merged predictions split along map instances
    uint64_t merged_fragments = 0;       ///< map instances merged into another one
    uint64_t semantic_updates = 0;
    uint64_t instance_updates = 0;
    uint64_t ray_steps = 0;              ///< voxels visited by the free-space rays
    double seconds_projection = 0;       ///< pixels to voxels, sample sums, voxel creation
    double seconds_ndt = 0;              ///< NDT shape and hit log-odds update
    /// Free-space rays and their misses. With several threads the workers walk
    /// rays during matching and the histograms: this is then the rest of the
    /// walk and the misses, and the walk's share is in those two.
    double seconds_occupancy = 0;
    double seconds_matching = 0;         ///< back-projection (vtou) and IoU matching (see above)
    double seconds_histograms = 0;       ///< semantic and instance histogram updates (see above)
    /// With several threads: the workers' time in the frame's tasks (summed
    /// over workers) and the caller's time waiting for them; so the frame's
    /// busy thread time is the caller's wall time minus the waiting plus this.
    double seconds_workers_busy = 0;
    double seconds_caller_waiting = 0;
    double secondsTotal() const
    {
        return seconds_projection + seconds_ndt + seconds_occupancy + seconds_matching + seconds_histograms;
    }
    FrameStats& operator+=(const FrameStats& o);
};

/// A map instance after propagation.
struct MapInstance
{
    uint32_t id = 0;
    uint16_t semantic = 0;
    uint32_t voxel_count = 0;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< mean of the voxels' NDT means
    Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero();
    Eigen::Vector3d bbox_max = Eigen::Vector3d::Zero();
    /// Frames of this map in which a prediction was matched to it or created it.
    uint32_t frames_seen = 0;
    /// Its h^Z weight over its voxels / all h^Z weight there (1: no rival ids).
    float weight_share = 0;
    /// A score for AP and object queries: instanceConfidence(weight_share, frames_seen).
    double confidence = 0;
};

/// The map rendered into a camera. 0 = nothing / void.
struct RenderedView
{
    Image<float> depth;               ///< metres along the optical axis
    Image<uint16_t> semantic;         ///< argmax h^L
    Image<uint16_t> panoptic_semantic;///< semantic part of the propagated label
    Image<uint32_t> instance;         ///< instance part of the propagated label
};

/// Result of label_at(xyz).
struct PointLabel
{
    bool found = false;           ///< false: no occupied voxel near enough (void)
    uint16_t semantic = 0;        ///< argmax h^L of the chosen voxel
    PanopticLabel panoptic;       ///< propagated label of the chosen voxel
    double mahalanobis_sq = 0;    ///< of the query point under the chosen Gaussian
    uint32_t voxel = kNoRecord;   ///< index of the chosen voxel
};

struct RayWorker;      // integrate()'s per-thread free-space scratch
struct MaskFootprint;  // a voxel's back-projection into the image
struct MaskSpan;       // a run of its pixels in one image row
struct FramePixels;    // a frame as the stages read it (contiguous, float metres along z)
struct HitSlot;        // a voxel the frame hit, with its samples

class PanopticMap
{
   public:
    explicit PanopticMap(MapOptions options = {});
    ~PanopticMap();
    PanopticMap(const PanopticMap&);
    PanopticMap& operator=(const PanopticMap&);
    PanopticMap(PanopticMap&&) noexcept;
    PanopticMap& operator=(PanopticMap&&) noexcept;

    const MapOptions& options() const { return options_; }
    const VoxelGrid& grid() const { return grid_; }
    void clear();

    /// One frame update, paper §III-C..F. `T_world_cam` maps optical-camera
    /// coordinates to the world. Throws InputError (naming frame.source) for
    /// size mismatches or class ids outside the class set.
    FrameStats integrate(const PanopticFrame& frame, const Pose& T_world_cam);
    /// The same over the caller's buffers (uint16 or float depth, z or ray length,
    /// strided rows): nothing is copied that can be read in place (frame.h).
    FrameStats integrate(const FrameView& frame, const Pose& T_world_cam);

    // ---- queries (propagate labels lazily first)
    void render(const Pose& T_world_cam, const CameraIntrinsics& K, RenderedView& out) const;
    PointLabel labelAt(const Eigen::Vector3d& p_world) const;
    std::vector<MapInstance> instances() const;
    /// Propagated label of a voxel (by store index).
    PanopticLabel panopticLabel(uint32_t voxel) const;
    /// argmax h^L of a voxel (0 if unlabelled).
    uint16_t semanticLabel(uint32_t voxel) const;
    /// Forces label propagation now (e.g. before serialising).
    void finalize() const;

    bool isOccupied(const Voxel& v) const { return v.occ > options_.occupied_threshold; }
    /// The voxel's NDT shape (an empty one for voxels never hit).
    const NdtShape& shapeOf(const Voxel& v) const
    {
        static const NdtShape empty;
        return v.surface == kNoRecord ? empty : surfaces_[v.surface].shape;
    }
    /// True when the voxel has enough samples for its Gaussian to be used.
    bool hasGaussian(const Voxel& v) const { return shapeOf(v).n >= options_.ndt_min_samples; }
    NdtGaussian gaussianOf(const Voxel& v) const;
    /// The voxel's NDT mean if it has samples, else its centre.
    Eigen::Vector3d pointOf(uint32_t voxel) const;
    size_t occupiedCount() const;
    /// Bytes held by the voxel store, the record pools and the propagation cache.
    size_t memoryBytes() const;
    /// memoryBytes() by part.
    struct MemoryUse
    {
        size_t voxels = 0, surfaces = 0, labels = 0, instances = 0, propagation = 0;
        size_t total() const { return voxels + surfaces + labels + instances + propagation; }
    };
    MemoryUse memoryUse() const;

    // ---- raw state, for serialisation and visualisation
    const VoxelStore& voxels() const { return store_; }
    const RecordPool<SurfaceRecord>& surfaceRecords() const { return surfaces_; }
    const RecordPool<LabelRecord>& labelRecords() const { return labels_; }
    const RecordPool<InstanceRecord>& instanceRecords() const { return instance_records_; }
    uint32_t nextInstanceId() const { return next_instance_id_; }
    const LabelRecord* labelsOf(const Voxel& v) const
    {
        if (v.surface == kNoRecord) return nullptr;
        const uint32_t l = surfaces_[v.surface].labels;
        return l == kNoRecord ? nullptr : &labels_[l];
    }
    const InstanceRecord* instancesOf(const LabelRecord& r) const
    {
        return r.instances == kNoRecord ? nullptr : &instance_records_[r.instances];
    }
    /// The classes of a voxel's h^L beyond its label record (semantic_eviction =
    /// false), or nullptr: pass it to the predicates of instance_rules.h.
    const SemanticSpill* spillOf(const Voxel& v) const
    {
        if (spills_.empty() || v.surface == kNoRecord) return nullptr;
        return spills_.find(surfaces_[v.surface].labels);
    }
    const SemanticSpills& semanticSpills() const { return spills_; }
    /// integrate() forgets the ids no record holds any more (their frames seen
    /// and fragment evidence: such an id is never matched again) each time the
    /// id counter passes a multiple of this, so that a map that runs for hours
    /// keeps no entry for every id it ever made.
    static constexpr uint32_t kDeadInstanceSweep = 4096;
    /// Frames in which each instance was matched or created, sorted by id (see
    /// kDeadInstanceSweep).
    std::vector<std::pair<uint32_t, uint32_t>> instanceFrames() const;
    /// Replaces them (after restore(); ids must be below nextInstanceId()).
    void restoreInstanceFrames(const std::vector<std::pair<uint32_t, uint32_t>>& frames);
    /// Replaces the spills (after restore()); each must belong to a full label
    /// record, hold classes of the class set the record does not, and weigh at
    /// most its smallest entry (throws std::invalid_argument naming the record).
    void restoreSpills(const std::vector<std::pair<uint32_t, SemanticSpill>>& spills);
    /// Renames map instances (e.g. to carry ids over from the previous
    /// short-term map); `rename(id)` returns the new id, or id to keep it. The
    /// id counter moves past every id in use. Ids outside [first, last] are
    /// kept without asking `rename` (a merge of a few ids in a large map).
    void renameInstances(const std::function<uint32_t(uint32_t)>& rename, uint32_t first = 1,
                         uint32_t last = UINT32_MAX);
    /// Lets new instance ids start at `id` or later (globally unique ids across maps).
    void reserveInstanceIds(uint32_t id) { next_instance_id_ = std::max(next_instance_id_, id); }

    /// Replaces the whole state; validates every cross-index (throws
    /// std::invalid_argument naming the first inconsistency).
    void restore(const std::vector<uint64_t>& keys, std::vector<Voxel> voxels, std::vector<SurfaceRecord> surfaces,
                 std::vector<LabelRecord> labels, std::vector<InstanceRecord> instance_records,
                 uint32_t next_instance_id);

    /// Evidence for merging fragments (option fragment_merge_frames): for a pair
    /// of map instances a < b, the frames one prediction covered both (joint) and
    /// two covered them apart. Part of the map's state (saved with it).
    struct PairEvidence
    {
        uint32_t a = 0, b = 0, joint = 0, apart = 0;
        bool operator==(const PairEvidence& o) const
        {
            return a == o.a && b == o.b && joint == o.joint && apart == o.apart;
        }
    };
    /// Sorted by (a, b).
    std::vector<PairEvidence> pairEvidence() const;
    /// Replaces it (after restore()).
    void restorePairEvidence(const std::vector<PairEvidence>& evidence);

   private:
    struct Scratch;
    struct Propagation;

    void validateClasses(const FramePixels& f) const;
    Scratch& scratch();
    void projectPixels(const FramePixels& f, const Pose& T, FrameStats& st);
    void projectBand(const FramePixels& f, const Pose& T, int band, int bands);
    void updateShapes(FrameStats& st);
    /// The ray stage in three steps: its rays and shares; one piece of the walk
    /// (a chunk of rays on `thread`, false when none is left), which the
    /// workers take while the caller matches instances and updates the
    /// histograms; then the misses.
    void prepareRays(const Pose& T);
    bool castRayPiece(int thread);
    void finishOccupancy(FrameStats& st);
    void castRays(const Eigen::Vector3d& origin, size_t first_ray, size_t end_ray, RayWorker& worker);
    void applyMisses(FrameStats& st);
    void matchInstances(const FramePixels& f, const Pose& T, FrameStats& st);
    /// Prefetches the records of the voxels a few hits after h (of hits[.., end)).
    void prefetchRecordChain(const HitSlot* hits, uint32_t h, uint32_t end) const;
    void predictedBand(const FramePixels& f, int band, int bands);
    /// vtou of one voxel: where it lies in the image.
    MaskFootprint maskFootprint(uint32_t voxel, const Pose& T_cam_world, const CameraIntrinsics& K) const;
    /// Prefetches the image rows a footprint covers (the next voxel's, while this one is walked).
    void prefetchFootprint(const MaskFootprint& fp, const FramePixels& f) const;
    /// The footprint's pixels that pass the depth test, as runs along its rows
    /// of one predicted instance each, in raster order; returns their number
    /// (at most the footprint's box area).
    uint32_t footprintSpans(const MaskFootprint& fp, const FramePixels& f, MaskSpan* out);
    void classifyMapInstances();
    void collectFragmentEvidence();
    void mergeFragments(FrameStats& st);
    /// Drops the frames seen and fragment evidence of ids no record holds any more.
    void forgetDeadInstances();
    void splitMergedPredictions(const FramePixels& f, FrameStats& st);
    void updateHistograms(const FramePixels& f, FrameStats& st);
    void histogramTask(const FramePixels& f, int task);
    void resetVoxelContents(Voxel& v);
    void invalidate() { propagated_valid_ = false; }
    void ensurePropagated() const;
    /// The instance a voxel takes in propagation (pthing and its top id), or 0.
    uint32_t propagatedInstance(uint32_t voxel) const;
    uint32_t topInstance(const Voxel& v) const;
    /// The top h^Z entry of an occupied voxel whether or not pthing holds, or 0.
    uint32_t strongestInstance(const Voxel& v) const;
    void classifyInstances() const;
    /// `instance`: every voxel's propagated instance so far, updated in place.
    void absorbFragments(std::vector<uint32_t>& instance) const;
    /// The propagated label of a voxel with semantic evidence `rec` and instance `instance`.
    PanopticLabel labelledLabel(const LabelRecord& rec, uint32_t instance) const;
    void fillUnlabelled(std::vector<uint32_t>& instance) const;

    MapOptions options_;
    VoxelGrid grid_;
    VoxelStore store_;
    RecordPool<SurfaceRecord> surfaces_;
    RecordPool<LabelRecord> labels_;
    RecordPool<InstanceRecord> instance_records_;
    SemanticSpills spills_;  ///< h^L beyond the records (semantic_eviction = false)
    tsl::robin_map<uint32_t, uint32_t> instance_frames_;  ///< instance id -> frames seen
    uint32_t next_instance_id_ = 1;
    double min_var_ = 0;

    std::unique_ptr<Scratch> scratch_;
    mutable std::unique_ptr<Propagation> prop_;
    mutable bool propagated_valid_ = false;
};

}  // namespace pndt
