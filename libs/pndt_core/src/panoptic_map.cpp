// PanopticMap: construction, the frame-update sequence, state access.
#include "frame_pixels.h"
#include "map_scratch.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iterator>
#include <stdexcept>

namespace pndt
{
FrameStats& FrameStats::operator+=(const FrameStats& o)
{
    pixels += o.pixels;
    valid_pixels += o.valid_pixels;
    skipped_invalid_depth += o.skipped_invalid_depth;
    skipped_over_range += o.skipped_over_range;
    skipped_outside_grid += o.skipped_outside_grid;
    hit_voxels += o.hit_voxels;
    rays += o.rays;
    ray_steps += o.ray_steps;
    missed_voxels += o.missed_voxels;
    predicted_instances += o.predicted_instances;
    matched_instances += o.matched_instances;
    new_instances += o.new_instances;
    ambiguous_instances += o.ambiguous_instances;
    split_predictions += o.split_predictions;
    merged_fragments += o.merged_fragments;
    semantic_updates += o.semantic_updates;
    instance_updates += o.instance_updates;
    seconds_projection += o.seconds_projection;
    seconds_ndt += o.seconds_ndt;
    seconds_occupancy += o.seconds_occupancy;
    seconds_matching += o.seconds_matching;
    seconds_histograms += o.seconds_histograms;
    seconds_workers_busy += o.seconds_workers_busy;
    seconds_caller_waiting += o.seconds_caller_waiting;
    return *this;
}

PanopticMap::PanopticMap(MapOptions options)
    : options_(std::move(options)), scratch_(std::make_unique<Scratch>()), prop_(std::make_unique<Propagation>())
{
    options_.validate();
    grid_ = VoxelGrid(options_.voxel_size);
    const double min_sigma = options_.ndt_min_sigma_ratio * options_.voxel_size;
    min_var_ = min_sigma * min_sigma;
}

PanopticMap::~PanopticMap() = default;
PanopticMap::PanopticMap(PanopticMap&&) noexcept = default;
PanopticMap& PanopticMap::operator=(PanopticMap&&) noexcept = default;

PanopticMap::PanopticMap(const PanopticMap& o)
    : options_(o.options_),
      grid_(o.grid_),
      store_(o.store_),
      surfaces_(o.surfaces_),
      labels_(o.labels_),
      instance_records_(o.instance_records_),
      spills_(o.spills_),
      instance_frames_(o.instance_frames_),
      next_instance_id_(o.next_instance_id_),
      min_var_(o.min_var_),
      scratch_(std::make_unique<Scratch>()),
      prop_(std::make_unique<Propagation>())
{
    scratch_->pair_evidence = o.scratch_->pair_evidence;
}

std::vector<PanopticMap::PairEvidence> PanopticMap::pairEvidence() const
{
    std::vector<PairEvidence> out;
    out.reserve(scratch_->pair_evidence.size());
    for (const auto& [key, c] : scratch_->pair_evidence)
        out.push_back({uint32_t(key >> 32), uint32_t(key), c.joint, c.apart});
    std::sort(out.begin(), out.end(),
              [](const PairEvidence& x, const PairEvidence& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
    return out;
}

void PanopticMap::restorePairEvidence(const std::vector<PairEvidence>& evidence)
{
    auto& table = scratch_->pair_evidence;
    table.clear();
    for (const PairEvidence& e : evidence)
    {
        if (e.a == 0 || e.a >= e.b)
            throw std::invalid_argument(fmt::format("pair evidence ({}, {}): ids must be 0 < a < b", e.a, e.b));
        table[(uint64_t(e.a) << 32) | e.b] = {e.joint, e.apart};
    }
}

PanopticMap& PanopticMap::operator=(const PanopticMap& o)
{
    if (this != &o) *this = PanopticMap(o);
    return *this;
}

void PanopticMap::clear()
{
    store_.clear();
    surfaces_.clear();
    labels_.clear();
    instance_records_.clear();
    spills_.clear();
    instance_frames_.clear();
    next_instance_id_ = 1;
    scratch_->pair_evidence.clear();
    invalidate();
}

NdtGaussian PanopticMap::gaussianOf(const Voxel& v) const { return NdtGaussian::fromShape(shapeOf(v), min_var_); }

Eigen::Vector3d PanopticMap::pointOf(uint32_t voxel) const
{
    const NdtShape& s = shapeOf(store_[voxel]);
    return s.n > 0 ? s.meanVec() : grid_.center(store_.key(voxel));
}

PanopticMap::Scratch& PanopticMap::scratch()
{
    Scratch& s = *scratch_;
    const int threads = options_.resolvedThreads();
    if (s.threads != threads || (threads > 1 && !s.pool))
    {
        s.pool = threads > 1 ? std::make_unique<WorkerPool>(threads, options_.pin_threads) : nullptr;
        s.threads = threads;
    }
    return s;
}

void PanopticMap::validateClasses(const FramePixels& f) const
{
    // One branch-free pass for the common case (in parallel), the offending
    // pixel only on error.
    const uint16_t* labels = f.semantic.data.data();
    const size_t n = f.semantic.data.size();
    const auto maxClass = [&](size_t i0, size_t i1) {
        uint16_t m = 0;
        for (size_t i = i0; i < i1; ++i) m = std::max(m, labels[i]);
        return m;
    };
    uint16_t max_class = 0;
    WorkerPool* pool = scratch_->pool.get();
    if (pool && n >= (size_t(1) << 16))
    {
        const int tasks = 4 * pool->threads();
        std::atomic<uint16_t> shared_max{0};
        pool->run(tasks, [&](int t) {
            const uint16_t m = maxClass(n * size_t(t) / size_t(tasks), n * size_t(t + 1) / size_t(tasks));
            for (uint16_t cur = shared_max.load(); m > cur && !shared_max.compare_exchange_weak(cur, m);)
            {
            }
        });
        max_class = shared_max.load();
    }
    else
        max_class = maxClass(0, n);
    if (max_class < options_.classes.size()) return;
    for (size_t i = 0; i < f.semantic.data.size(); ++i)
        if (!options_.classes.contains(f.semantic.data[i]))
            throw InputError(fmt::format("{}: class id {} at pixel (row {}, col {}) is outside the class set "
                                         "(0..{})",
                                         f.where(), f.semantic.data[i], i / f.depth.width, i % f.depth.width,
                                         options_.classes.size() - 1));
}

FrameStats PanopticMap::integrate(const PanopticFrame& f, const Pose& T_world_cam)
{
    // An owned image whose pixel count disagrees with its size cannot be viewed.
    const auto checkOwned = [&](const auto& img, const char* what) {
        if (img.data.size() != size_t(img.width) * size_t(std::max(img.height, 0)) || img.width < 0 || img.height < 0)
            throw InputError(fmt::format("{}: {} image holds {} pixels but is {}x{}",
                                         f.source.empty() ? std::string("frame") : f.source, what, img.data.size(),
                                         img.width, img.height));
    };
    checkOwned(f.depth, "depth");
    checkOwned(f.semantic, "semantic");
    checkOwned(f.semantic_score, "semantic score");
    checkOwned(f.instance, "instance");
    checkOwned(f.panoptic_score, "panoptic score");
    return integrate(FrameView(f), T_world_cam);
}

FrameStats PanopticMap::integrate(const FrameView& view, const Pose& T_world_cam)
{
    using Clock = std::chrono::steady_clock;
    const auto seconds = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration<double>(b - a).count();
    };
    // Workers stay awake through the frame's stages (they check the frame too).
    WorkerPool* const pool = scratch().pool.get();
    const WorkerPool::Burst burst(pool);
    const auto workers_busy = pool ? pool->workersBusy() : std::chrono::nanoseconds(0);
    const auto caller_waiting = pool ? pool->callerWaiting() : std::chrono::nanoseconds(0);
    const FramePixels frame = resolveFrame(view, options_, scratch_->input);
    validateClasses(frame);
    if (const std::string problem = poseInvalidReason(T_world_cam); !problem.empty())
        throw InputError(fmt::format("{}: {}", frame.where(), problem));

    FrameStats st;
    invalidate();
    const uint32_t ids_before = next_instance_id_;
    const auto t0 = Clock::now();
    projectPixels(frame, T_world_cam, st);
    const auto t1 = Clock::now();
    updateShapes(st);
    const auto t2 = Clock::now();
    // The ray walk reads none of what matching and the histograms read or write
    // (rays skip this frame's hit voxels, those two touch only them and their
    // records, and the walk writes only its own blocks), so the workers walk rays
    // while the caller runs those two stages, taking the stages' tasks between
    // chunks of rays. The misses, which write the map, come after all three.
    prepareRays(T_world_cam);
    auto piece = [this](int thread) { return castRayPiece(thread); };
    Clock::time_point t3, t4, t5;
    {
        WorkerPool::Background rays(scratch_->pool.get(), piece);
        if (frame.hasInstances()) matchInstances(frame, T_world_cam, st);
        t3 = Clock::now();
        if (frame.hasLabels()) updateHistograms(frame, st);
        t4 = Clock::now();
        rays.finish();
    }
    finishOccupancy(st);
    t5 = Clock::now();
    mergeFragments(st);
    // Every kDeadInstanceSweep ids made (a point that follows from the map's
    // state alone, so that a saved and reloaded map forgets what the original does).
    if (next_instance_id_ / kDeadInstanceSweep != ids_before / kDeadInstanceSweep) forgetDeadInstances();
    const auto t6 = Clock::now();
    st.seconds_projection = seconds(t0, t1);
    st.seconds_ndt = seconds(t1, t2);
    st.seconds_matching = seconds(t2, t3);
    st.seconds_histograms = seconds(t3, t4) + seconds(t5, t6);
    st.seconds_occupancy = seconds(t4, t5);
    if (pool)
    {
        st.seconds_workers_busy = std::chrono::duration<double>(pool->workersBusy() - workers_busy).count();
        st.seconds_caller_waiting = std::chrono::duration<double>(pool->callerWaiting() - caller_waiting).count();
    }
    return st;
}

void PanopticMap::resetVoxelContents(Voxel& v)
{
    if (v.surface == kNoRecord) return;
    SurfaceRecord& sr = surfaces_[v.surface];
    sr.shape.reset();
    if (sr.labels == kNoRecord) return;
    LabelRecord& r = labels_[sr.labels];
    spills_.erase(sr.labels);
    const uint32_t inst = r.instances;
    r = LabelRecord{};
    r.instances = inst;  // keep the pooled record for reuse
    if (inst != kNoRecord) instance_records_[inst] = InstanceRecord{};
}

size_t PanopticMap::occupiedCount() const
{
    size_t n = 0;
    for (const Voxel& v : store_.voxels()) n += isOccupied(v);
    return n;
}

PanopticMap::MemoryUse PanopticMap::memoryUse() const
{
    MemoryUse m;
    m.voxels = store_.memoryBytes();
    m.surfaces = surfaces_.bytesUsed();
    m.labels = labels_.bytesUsed() + spills_.memoryBytes();
    m.instances = instance_records_.bytesUsed();
    m.propagation = prop_->instance_class.bucket_count() * (sizeof(std::pair<uint32_t, uint16_t>) + 4) +
                    prop_->instances.capacity() * sizeof(MapInstance) +
                    (prop_->instance_of_voxel.bucket_count() + prop_->absorbed_into.bucket_count()) *
                        (sizeof(std::pair<uint32_t, uint32_t>) + 4) +
                    prop_->filled.bucket_count() * (sizeof(std::pair<uint32_t, PanopticLabel>) + 4);
    return m;
}

size_t PanopticMap::memoryBytes() const { return memoryUse().total(); }

void PanopticMap::restore(const std::vector<uint64_t>& keys, std::vector<Voxel> voxels,
                          std::vector<SurfaceRecord> surfaces, std::vector<LabelRecord> labels,
                          std::vector<InstanceRecord> instance_records, uint32_t next_instance_id)
{
    // Each record belongs to at most one owner (the parallel updates rely on it).
    std::vector<uint8_t> owned(std::max({surfaces.size(), labels.size(), instance_records.size()}), 0);
    const auto claim = [&](uint32_t r, uint8_t bit, const char* what, const char* owner, size_t i) {
        if (owned[r] & bit)
            throw std::invalid_argument(fmt::format("{} {} refers to {} {}, which another one holds", owner, i, what, r));
        owned[r] |= bit;
    };
    for (size_t i = 0; i < voxels.size(); ++i)
    {
        const Voxel& v = voxels[i];
        if (v.surface != kNoRecord && v.surface >= surfaces.size())
            throw std::invalid_argument(fmt::format("voxel {} refers to surface record {} of {}", i, v.surface,
                                                    surfaces.size()));
        if (!std::isfinite(v.occ))
            throw std::invalid_argument(fmt::format("voxel {} has a non-finite occupancy", i));
        if (v.surface != kNoRecord) claim(v.surface, 1, "surface record", "voxel", i);
    }
    for (size_t i = 0; i < surfaces.size(); ++i)
    {
        const SurfaceRecord& s = surfaces[i];
        if (s.labels != kNoRecord && s.labels >= labels.size())
            throw std::invalid_argument(fmt::format("surface record {} refers to label record {} of {}", i, s.labels,
                                                    labels.size()));
        if (s.labels != kNoRecord) claim(s.labels, 2, "label record", "surface record", i);
    }
    for (size_t i = 0; i < labels.size(); ++i)
    {
        const LabelRecord& r = labels[i];
        if (r.instances != kNoRecord && r.instances >= instance_records.size())
            throw std::invalid_argument(fmt::format("label record {} refers to instance record {} of {}", i,
                                                    r.instances, instance_records.size()));
        if (r.instances != kNoRecord) claim(r.instances, 4, "instance record", "label record", i);
        for (int j = r.semantic.size(); j < LabelRecord::kSemanticCapacity; ++j)
            if (r.semantic.ids[j] != 0)
                throw std::invalid_argument(fmt::format("label record {} has a class after a free entry", i));
        for (int j = 0, n = r.semantic.size(); j < n; ++j)
            if (!options_.classes.contains(r.semantic.ids[j]) && !(options_.void_bin && r.semantic.ids[j] == kVoidBin))
                throw std::invalid_argument(
                    fmt::format("label record {} holds class {} outside the class set", i, r.semantic.ids[j]));
    }
    for (size_t i = 0; i < instance_records.size(); ++i)
    {
        const auto& h = instance_records[i].hist;
        for (int j = h.size(); j < h.kCapacity; ++j)
            if (h.ids[j] != 0)
                throw std::invalid_argument(fmt::format("instance record {} has an id after a free entry", i));
        for (int j = 0, n = h.size(); j < n; ++j)
            if (h.ids[j] >= next_instance_id)
                throw std::invalid_argument(fmt::format("instance record {} holds id {} (next id is {})", i,
                                                        h.ids[j], next_instance_id));
    }
    store_.assign(keys, std::move(voxels));
    surfaces_.assign(surfaces.begin(), surfaces.end());
    labels_.assign(labels.begin(), labels.end());
    instance_records_.assign(instance_records.begin(), instance_records.end());
    next_instance_id_ = next_instance_id;
    spills_.clear();
    instance_frames_.clear();
    scratch_->pair_evidence.clear();
    invalidate();
}

std::vector<std::pair<uint32_t, uint32_t>> PanopticMap::instanceFrames() const
{
    std::vector<std::pair<uint32_t, uint32_t>> out(instance_frames_.begin(), instance_frames_.end());
    std::sort(out.begin(), out.end());
    return out;
}

void PanopticMap::restoreInstanceFrames(const std::vector<std::pair<uint32_t, uint32_t>>& frames)
{
    instance_frames_.clear();
    for (const auto& [id, n] : frames)
    {
        if (id == 0 || id >= next_instance_id_)
            throw std::invalid_argument(
                fmt::format("frames seen of instance {}: ids must be 0 < id < {}", id, next_instance_id_));
        if (!instance_frames_.emplace(id, n).second)
            throw std::invalid_argument(fmt::format("frames seen of instance {} given twice", id));
    }
    invalidate();
}

void PanopticMap::restoreSpills(const std::vector<std::pair<uint32_t, SemanticSpill>>& spills)
{
    spills_.clear();
    for (const auto& [li, spill] : spills)
    {
        if (li >= labels_.size())
            throw std::invalid_argument(fmt::format("semantic spill of label record {} of {}", li, labels_.size()));
        const auto& h = labels_[li].semantic;
        if (h.size() < LabelRecord::kSemanticCapacity)
            throw std::invalid_argument(fmt::format("label record {} has a semantic spill but room in its record", li));
        const float smallest = h.weight(LabelRecord::kSemanticCapacity - 1);
        for (const auto& e : spill.entries)
        {
            if (!(options_.classes.contains(e.cls) || (options_.void_bin && e.cls == kVoidBin)) || h.indexOf(e.cls) >= 0)
                throw std::invalid_argument(
                    fmt::format("semantic spill of label record {} holds class {} outside the class set or twice", li, e.cls));
            // (Quantised record weights round: a spilled weight may exceed the smallest by that much.)
            if (!(e.weight > 0.f) || e.weight > smallest * (1.f + 1e-3f) + 1e-6f)
                throw std::invalid_argument(fmt::format(
                    "semantic spill of label record {}: class {} weighs {}, outside (0, {}]", li, e.cls, e.weight, smallest));
        }
        if (spills_.find(li))
            throw std::invalid_argument(fmt::format("label record {} has two semantic spills", li));
        spills_.set(li, spill);
    }
    invalidate();
}

void PanopticMap::renameInstances(const std::function<uint32_t(uint32_t)>& rename, uint32_t first, uint32_t last)
{
    const auto renamed = [&](uint32_t id) { return id < first || id > last ? id : rename(id); };
    for (InstanceRecord& rec : instance_records_)
    {
        auto& h = rec.hist;
        uint32_t ids[InstanceHistogram::kCapacity];
        bool any = false;
        const int n = h.size();
        for (int i = 0; i < n; ++i)
        {
            ids[i] = renamed(h.ids[i]);
            if (ids[i] == 0) throw std::invalid_argument("renameInstances: instance id 0 is reserved");
            next_instance_id_ = std::max(next_instance_id_, ids[i] + 1);
            any |= ids[i] != h.ids[i];
        }
        // Most records hold no renamed id and stay as they are: rebuilding every
        // one made this the largest serial part of a frame with fragment merges.
        if (!any) continue;
        // Two ids may be renamed to one: merge their weights, keep the order.
        InstanceHistogram renamed;
        for (int i = 0; i < n; ++i) renamed.add(ids[i], h.weight(i));
        h = renamed;
    }
    // Frames seen follow the ids; merged ones keep the larger count (the frames
    // overlap). Only the renamed ids' entries move: the table holds every id the
    // map made in the last few thousand (forgetDeadInstances), and rebuilding it
    // cost ~25 ns an entry on every frame with a fragment merge.
    auto& moved = scratch_->moved_frames;
    moved.clear();
    const auto take = [&](uint32_t id, uint32_t n) {
        const uint32_t to = renamed(id);
        if (to == id) return false;
        moved.emplace_back(to, n);
        return true;
    };
    if (uint64_t(last) - first < instance_frames_.size())
    {
        for (uint64_t id = first; id <= last; ++id)
            if (const auto it = instance_frames_.find(uint32_t(id)); it != instance_frames_.end() && take(it->first, it->second))
                instance_frames_.erase(it);
    }
    else
        for (auto it = instance_frames_.begin(); it != instance_frames_.end();)
            it = take(it->first, it->second) ? instance_frames_.erase(it) : std::next(it);
    for (const auto& [to, n] : moved)
    {
        uint32_t& m = instance_frames_[to];
        m = std::max(m, n);
    }
    invalidate();
}

void PanopticMap::forgetDeadInstances()
{
    // An id that no record holds can never be matched again (new instances take
    // new ids): its frames seen and fragment evidence are dropped, so that a map
    // that runs for hours does not keep an entry for every id it ever made.
    Scratch& s = *scratch_;
    auto& live = s.live_ids;
    live.assign(size_t(next_instance_id_) / 64 + 1, 0);
    for (const InstanceRecord& rec : instance_records_)
        for (int i = 0, n = rec.hist.size(); i < n; ++i)
        {
            const uint32_t id = rec.hist.ids[i];
            if (id < next_instance_id_) live[id >> 6] |= uint64_t(1) << (id & 63);
        }
    const auto alive = [&](uint32_t id) { return id < next_instance_id_ && (live[id >> 6] >> (id & 63) & 1); };
    for (auto it = instance_frames_.begin(); it != instance_frames_.end();)
        it = alive(it->first) ? std::next(it) : instance_frames_.erase(it);
    for (auto it = s.pair_evidence.begin(); it != s.pair_evidence.end();)
        it = alive(uint32_t(it->first >> 32)) && alive(uint32_t(it->first)) ? std::next(it) : s.pair_evidence.erase(it);
}

}  // namespace pndt
