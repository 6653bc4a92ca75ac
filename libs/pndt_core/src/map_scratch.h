// Per-frame working memory of PanopticMap, kept between frames so the hot path
// does not allocate once the buffers have grown to the frame size.
#pragma once

#include <pndt/gaussian.h>
#include <pndt/panoptic_map.h>
#include <tsl/robin_map.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

#include "frame_pixels.h"
#include "mask_footprint.h"
#include "mask_row_kernels.h"
#include "projection_kernels.h"
#include "worker_pool.h"

namespace pndt
{
/// pixel_predicted of a pixel without valid depth.
constexpr int32_t kUnmappedPixel = -2;

/// One flag per band, set by the thread that finished it (release) and read by
/// the band merger (acquire).
class BandFlags
{
   public:
    void reset(int n)
    {
        if (n > count_)
        {
            flags_ = std::make_unique<std::atomic<bool>[]>(size_t(n));
            count_ = n;
        }
        for (int i = 0; i < n; ++i) flags_[size_t(i)].store(false, std::memory_order_relaxed);
    }
    void set(int i) { flags_[size_t(i)].store(true, std::memory_order_release); }
    bool isSet(int i) const { return flags_[size_t(i)].load(std::memory_order_acquire); }

   private:
    std::unique_ptr<std::atomic<bool>[]> flags_;
    int count_ = 0;
};

/// All samples of this frame in one endpoint voxel.
struct HitSlot
{
    uint64_t key = 0;            ///< packed voxel key
    uint32_t voxel = kNoRecord;  ///< store index (set once the band results are merged)
    uint32_t count = 0;
    int64_t s[3] = {0, 0, 0};               ///< sum of the quantised offsets
    int64_t ss[6] = {0, 0, 0, 0, 0, 0};     ///< sum of their products xx xy xz yy yz zz

    void reset(uint64_t k)
    {
        key = k;
        voxel = kNoRecord;
        count = 0;
        s[0] = s[1] = s[2] = 0;
        for (auto& x : ss) x = 0;
    }
    void add(int64_t x, int64_t y, int64_t z)
    {
        ++count;
        s[0] += x;
        s[1] += y;
        s[2] += z;
        ss[0] += x * x;
        ss[1] += x * y;
        ss[2] += x * z;
        ss[3] += y * y;
        ss[4] += y * z;
        ss[5] += z * z;
    }
    void add(const HitSlot& o)
    {
        count += o.count;
        for (int i = 0; i < 3; ++i) s[i] += o.s[i];
        for (int i = 0; i < 6; ++i) ss[i] += o.ss[i];
    }
};

/// Consecutive mapped pixels of one image row in one voxel: pixels [begin, end)
/// all have local slot `slot` of their band.
struct PixelSpan
{
    uint32_t begin, end, slot;
};

/// Room for one span per pixel of a band, allocated uninitialised (no page is
/// touched before it is written) and written through a plain pointer.
class SpanBuffer
{
   public:
    void reserve(size_t n)
    {
        if (n <= capacity_) return;
        data_.reset(new PixelSpan[n]);
        capacity_ = n;
        size_ = 0;
    }
    PixelSpan* data() { return data_.get(); }
    void setSize(size_t n) { size_ = n; }
    void clear() { size_ = 0; }
    size_t size() const { return size_; }
    const PixelSpan* begin() const { return data_.get(); }
    const PixelSpan* end() const { return data_.get() + size_; }

   private:
    std::unique_ptr<PixelSpan[]> data_;
    size_t size_ = 0, capacity_ = 0;
};

/// The rows of the image one task projects: its own voxel table and counters.
/// alignas(64), as the other per-task structs below: tasks on different
/// threads write their own, which must not share a cache line.
struct alignas(64) ProjectionBand
{
    tsl::robin_map<uint64_t, uint32_t, PackedKeyHash> index;  ///< packed key -> local slot
    std::vector<HitSlot> hits;
    uint32_t count = 0;
    std::vector<uint32_t> remap;                 ///< local slot -> frame slot (identity in band 0)
    std::vector<Eigen::Vector3d> points;         ///< RayMode::PerPixel only
    std::vector<int32_t> last_row;               ///< per local slot: last image row it was seen in
    /// The band's mapped pixels in raster order, cut where the voxel changes or
    /// a pixel is not mapped: the histogram tasks walk these, not the pixels.
    SpanBuffer spans;
    uint32_t home_begin = 0, home_end = 0;       ///< frame slots first seen in this band
    int home_last_row = 0;                       ///< last row any of them reaches
    RowBuffer rows[2];
    uint64_t valid = 0, invalid = 0, over_range = 0, outside = 0;

    void clear()
    {
        index.clear();
        count = 0;
        points.clear();
        last_row.clear();
        spans.clear();
        valid = invalid = over_range = outside = 0;
    }
    HitSlot& newHit()
    {
        if (count == hits.size()) hits.emplace_back();
        return hits[count++];
    }
};

/// Per-ray misses (MissAccumulation::PerRay) are summed as integers in these
/// units: the sum is the same whichever thread cast which ray.
constexpr double kMissQuantum = 1.0 / (1 << 24);

/// Gaussian of a voxel a ray passes, as the miss rule needs it.
struct MissGaussian
{
    Eigen::Vector3d mean;
    Eigen::Matrix3d info;
    float delta = 0;  ///< strongest (most negative) miss of this task's rays so far
    int64_t sum = 0;  ///< PerRay: sum of this task's rays' misses, in kMissQuantum
};

/// One brick as seen by one ray task in this frame.
struct RayBlock
{
    static constexpr int32_t kUnseen = 0;     ///< not classified yet
    static constexpr int32_t kSkip = -1;      ///< hit in this frame: no miss
    static constexpr int32_t kConstant = -2;  ///< no usable Gaussian: the constant miss
    uint64_t brick_key = 0;
    const uint32_t* slots = nullptr;  ///< the store brick's slot table, or nullptr
    /// kUnseen, kSkip, kConstant (the miss is log_odds_miss whatever the ray) or
    /// 1 + index of the voxel's MissGaussian, which holds its strongest miss.
    int32_t state[VoxelStore::kBrickSlots];
    /// PerRay: rays of this task that crossed a kConstant slot.
    uint32_t crossings[VoxelStore::kBrickSlots];
    uint64_t touched[VoxelStore::kBrickSlots / 64];  ///< slots visited in this use
    RayBlock* neighbour[6];  ///< this task's blocks of the 6 face neighbours (-x,+x,-y,+y,-z,+z), once known
};

/// What one ray task keeps: its bricks and the Gaussians it computed.
struct alignas(64) RayWorker
{
    tsl::robin_map<uint64_t, uint32_t, PackedKeyHash> block_of;  ///< brick key -> block
    std::vector<std::unique_ptr<RayBlock>> blocks;
    uint32_t block_count = 0;
    std::vector<MissGaussian> gaussians;
    uint32_t gaussian_count = 0;
    uint64_t steps = 0;

    void clear()
    {
        block_of.clear();
        block_count = 0;
        gaussian_count = 0;
        steps = 0;
    }
};

/// What one thread's pass over the misses leaves: the misses of voxels that
/// do not exist yet (created afterwards, in brick order) and counts.
struct alignas(64) MissChunk
{
    std::vector<uint16_t> slot;    ///< voxel in the brick, per miss
    std::vector<float> delta;      ///< its strongest miss
    size_t misses = 0;             ///< voxels that got a miss
    size_t gaussians = 0;          ///< distinct Gaussians the rays met

    void clear()
    {
        slot.clear();
        delta.clear();
        misses = gaussians = 0;
    }
};

/// Work in one contiguous share per thread, claimed in chunks: each thread
/// takes its own share first (the data its earlier work left in its cache),
/// then what is left of the others'. Any thread may end up with any chunk.
struct alignas(64) WorkShare
{
    std::atomic<size_t> next{0};
    size_t end = 0;
};
class WorkShares
{
   public:
    void reset(int threads)
    {
        if (count_ != threads) shares_ = std::make_unique<WorkShare[]>(size_t(threads));
        count_ = threads;
    }
    void set(int t, size_t begin, size_t end)
    {
        shares_[size_t(t)].next.store(begin);
        shares_[size_t(t)].end = end;
    }
    /// Calls fn(i0, i1, share) for chunks of at most `chunk` items until none is left.
    template <typename Fn>
    void drain(int thread, size_t chunk, Fn&& fn)
    {
        while (drainOne(thread, chunk, fn))
        {
        }
    }

    /// One chunk: the thread's own share first, then the others' in turn;
    /// false when none is left.
    template <typename Fn>
    bool drainOne(int thread, size_t chunk, Fn&& fn)
    {
        for (int k = 0; k < count_; ++k)
        {
            const int t = (thread + k) % count_;
            WorkShare& sh = shares_[size_t(t)];
            if (sh.next.load() >= sh.end) continue;
            if (const size_t i0 = sh.next.fetch_add(chunk); i0 < sh.end)
            {
                fn(i0, std::min(sh.end, i0 + chunk), t);
                return true;
            }
        }
        return false;
    }

   private:
    std::unique_ptr<WorkShare[]> shares_;
    int count_ = 0;
};

/// Predicted instances of a band of image rows, in order of first pixel.
struct alignas(64) PredictedBand
{
    tsl::robin_map<uint32_t, uint32_t> index;  ///< raw predicted id -> local index
    std::vector<uint32_t> ids;
    std::vector<uint64_t> area;                ///< mapped pixels
    std::vector<uint16_t> cls;                 ///< semantic class at its first pixel
    std::vector<int32_t> remap;                ///< local index -> frame index (identity in band 0)
};

/// A thing voxel seen in this frame, once per top-z instance: sorted by
/// (instance, voxel); `thing` indexes the frame's thing voxels (footprints and
/// pixel lists, computed once per voxel however many instances it has).
struct MaskCandidate
{
    uint32_t first = 0;   ///< map instance
    uint32_t second = 0;  ///< voxel (store index)
    uint32_t thing = 0;
    bool operator<(const MaskCandidate& o) const { return first != o.first ? first < o.first : second < o.second; }
};

/// Room for the frame's mask spans, allocated uninitialised and only grown.
class MaskSpanBuffer
{
   public:
    void reserve(size_t n)
    {
        if (n <= capacity_) return;
        n += n / 4;
        data_.reset(new MaskSpan[n]);
        capacity_ = n;
    }
    MaskSpan* data() { return data_.get(); }
    const MaskSpan* data() const { return data_.get(); }

   private:
    std::unique_ptr<MaskSpan[]> data_;
    size_t capacity_ = 0;
};

/// Per-thread state of the mask rasterisation: a bit per pixel (a pixel counts
/// once per mask; all clear between masks) and the thread's counts per map
/// instance (summed afterwards: integer sums, so any split of the work gives
/// the same totals).
struct alignas(64) MaskWorker
{
    std::vector<uint64_t> bits;
    std::vector<uint64_t> area;   ///< per group
    std::vector<uint64_t> inter;  ///< per group x predicted
};

/// One task of the mask rasterisation: group `group`'s pixels in rows
/// [H piece / pieces, H (piece + 1) / pieces).
struct MaskTask
{
    uint32_t group;
    uint32_t piece, pieces;
};

/// The records of a frame slot's voxel, looked up on its first pixel.
struct SlotRecords
{
    LabelRecord* label = nullptr;
    InstanceRecord* instance = nullptr;
    /// The voxel's runs while the pass is in other voxels (float weights: a run goes on
    /// across the voxel's rows and is flushed once, when its class or instance changes or
    /// at the end of the pass; the same additions in the same order as a flush per row).
    uint8_t run_l = 0;  ///< 0: no semantic run
    int8_t run_li = 0;
    int8_t run_zi = 0;
    uint32_t run_z = 0;  ///< 0: no instance run
    float run_lw = 0, run_zw = 0;
    uint32_t run_nl = 0, run_nz = 0;
};

/// One histogram task: the voxels of one projection band, and the records it created.
struct alignas(64) HistogramWorker
{
    /// A pixel's semantic update that found its voxel's record full without its
    /// class (semantic_eviction = false): applied through the map's spill after
    /// the pass, serially, in the task's pixel order.
    struct SpilledPixel
    {
        uint32_t slot;
        uint8_t cls;
        float score;
    };
    std::vector<SpilledPixel> spilled;
    uint64_t semantic_updates = 0, instance_updates = 0;
    std::vector<LabelRecord> labels;        ///< new records of this frame, until they join the pool
    std::vector<InstanceRecord> instances;
    std::vector<uint32_t> band_decision;  ///< per predicted index of the band being walked: its decision
};

struct PanopticMap::Scratch
{
    std::unique_ptr<WorkerPool> pool;
    int threads = 1;
    FrameInputBuffers input;  ///< converted depth / strided labels of FrameView input

    // projection
    ProjectionSetup projection;
    std::vector<int32_t> pixel_slot;      ///< per pixel: its band's local hit slot (remap: frame slot), -1 not mapped
    std::vector<ProjectionBand> bands;    ///< bands[0] holds the merged frame result
    int band_count = 1;                   ///< bands used by this frame (projection and predicted instances)
    MaskFootprintFn mask_footprint = &maskFootprintScalar;  ///< the vtou kernel of this frame (instance matching)
    std::vector<const int32_t*> row_remap;  ///< per image row: its band's remap (predicted index -> frame's)
    BandFlags band_done;                  ///< projected, not merged yet
    int merged_bands = 0;                 ///< bands [0, merged_bands) merged (under band_merge)
    std::mutex band_merge;
    std::vector<uint64_t> hit_bits;       ///< per voxel one bit: hit in this frame (until its rays are cast)
    bool hit_bits_set = false;            ///< set and not cleared yet (a frame that threw in between)
    std::vector<uint32_t> new_surfaces;   ///< per shape task: first of its new surface records (prefix sums)

    // free space
    std::vector<RayWorker> ray_workers;
    struct BlockRef
    {
        uint64_t brick_key;
        uint32_t worker, block;
        bool operator<(const BlockRef& o) const
        {
            return brick_key != o.brick_key ? brick_key < o.brick_key : worker < o.worker;
        }
    };
    std::vector<BlockRef> block_refs;
    WorkShares ray_shares;                               ///< per thread: a contiguous share of the rays
    Eigen::Vector3d ray_origin = Eigen::Vector3d::Zero(); ///< this frame's camera centre
    size_t ray_count = 0;                                ///< this frame's rays
    bool rays_parallel = false;                          ///< chunks for every thread (else one for the caller)
    size_t frame_bricks = 0, frame_gaussians = 0;  ///< distinct bricks and Gaussians the rays met
    std::vector<std::pair<size_t, size_t>> miss_groups;  ///< block_refs of one brick
    /// Per thread: the miss groups whose first block is its own.
    std::vector<std::vector<uint32_t>> own_groups;
    WorkShares group_shares;
    std::vector<MissChunk> miss_chunks;                  ///< per thread
    /// Per group: the chunk and range of its misses on voxels not created yet
    /// (begin == end: none).
    struct FreshMisses
    {
        uint32_t chunk = 0, begin = 0, end = 0;
    };
    std::vector<FreshMisses> fresh_misses;

    // instance matching
    std::vector<PredictedBand> predicted_bands;          ///< [0]: the frame's predicted instances
    std::vector<uint32_t> predicted_decision;            ///< matched/new map id, 0 = none
    std::vector<int32_t> pixel_predicted;                ///< per pixel its band's local index, -1 none, kUnmappedPixel
    std::vector<MaskCandidate> candidates;               ///< (map instance, voxel index, thing), sorted
    std::vector<std::vector<MaskCandidate>> candidate_parts;  ///< per task, sorted
    std::vector<std::vector<MaskCandidate>> candidate_sort_tmp;  ///< per task, sorting scratch
    std::vector<std::vector<MaskCandidate>> candidate_merge;     ///< two per task: the merge levels' outputs
    std::vector<std::vector<uint32_t>> thing_parts;      ///< per task: hit slots of its thing voxels
    std::vector<uint32_t> thing_base;                    ///< per task: index of its first thing voxel
    std::vector<uint32_t> thing_voxel;                   ///< per thing voxel of the frame: its store index
    MaskSpanBuffer mask_spans;                           ///< per thing voxel its vtou pixels as row spans
    std::vector<uint64_t> thing_spans;                   ///< per thing voxel: its first span (packed per task)
    std::vector<uint32_t> thing_span_count;              ///< per thing voxel: its spans
    std::vector<std::pair<size_t, size_t>> groups;       ///< candidates of one map instance
    std::vector<uint64_t> group_area;                    ///< per group: mask area
    std::vector<uint64_t> group_inter;                   ///< per group x predicted: intersection
    std::vector<MaskWorker> mask_workers;                ///< per thread
    std::vector<uint32_t> mask_order;                    ///< groups, most spans first
    std::vector<uint64_t> group_spans;                   ///< per group: its voxels' spans (the mask's work)
    std::vector<MaskTask> mask_tasks;                    ///< the masks' tasks, in mask_order
    std::vector<MaskFootprint> footprints;               ///< per thing voxel
    std::vector<double> iou;                             ///< per group x predicted
    std::vector<int32_t> assignment;                     ///< per predicted: group, kAssignNew/Ambiguous
    std::vector<std::vector<float>> class_mass;          ///< per task: per class, one group at a time
    std::vector<uint16_t> group_class;                   ///< per group: its thing class, 0 = none
    std::vector<uint32_t> split_stamp, split_id;         ///< per pixel: map id where a merge was split
    std::vector<std::pair<uint32_t, uint32_t>> splits;   ///< this frame's (group, predicted) splits, in order
    std::vector<uint16_t> own_class;                     ///< per candidate of a split group: its voxel's own thing class
    uint32_t split_counter = 0;
    bool split_pixels = false;                           ///< this frame split a prediction
    std::vector<int32_t> coverer;                        ///< per group: the prediction covering most of it, or -1

    /// Fragment evidence per pair of map instances (smaller id in the high half):
    /// frames one prediction covered both / two predictions covered them apart.
    /// Map state kept here because it changes with every frame like the scratch.
    struct PairCounts
    {
        uint32_t joint = 0, apart = 0;
    };
    tsl::robin_map<uint64_t, PairCounts> pair_evidence;
    std::vector<std::pair<uint32_t, uint32_t>> fragment_merges;  ///< (fragment, into), applied after the frame
    std::vector<std::pair<uint32_t, uint32_t>> moved_frames;     ///< renameInstances: (new id, frames seen)
    std::vector<uint64_t> live_ids;                               ///< forgetDeadInstances: a bit per id in a record

    // histograms
    std::vector<uint32_t> new_label;      ///< per hit slot: new record in its task's list, or kNoRecord
    std::vector<uint32_t> new_instance;
    std::vector<SlotRecords> slot_records;
    std::vector<HistogramWorker> hist_workers;  ///< per band
    std::vector<uint32_t> new_record_base;      ///< per band: first new label / instance record (prefix sums)

    /// The band that image row r (of H) belongs to: rows [H*b/B, H*(b+1)/B).
    int bandOfRow(int r, int H) const { return int((int64_t(band_count) * (r + 1) - 1) / H); }
    HitSlot* hits() { return bands[0].hits.data(); }
    uint32_t hitCount() const { return bands[0].count; }
};

/// Cached result of label propagation (paper step 7).
/// Voxel labels are not cached: a voxel's propagated label follows from its own
/// records and the class of its instance (panopticLabel()).
struct PanopticMap::Propagation
{
    tsl::robin_map<uint32_t, uint16_t> instance_class;  ///< map instance -> its thing class
    /// Voxels that take another instance than their top one (class_consistent_instances).
    tsl::robin_map<uint32_t, uint32_t> instance_of_voxel;
    /// Fragments joined to a touching instance of their class (fragment_absorb_ratio).
    tsl::robin_map<uint32_t, uint32_t> absorbed_into;
    /// Labels of occupied voxels without semantic evidence (label_fill_distance).
    tsl::robin_map<uint32_t, PanopticLabel> filled;
    std::vector<MapInstance> instances;                 ///< sorted by id
};

}  // namespace pndt
