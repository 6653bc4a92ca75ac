// Paper steps 5-6: instance and semantic histogram updates per mapped pixel.
//
// Parallel and deterministic: a voxel belongs to the projection band that saw
// it first; the band's task walks the pixel spans (a row's consecutive pixels
// in one voxel) of its band and of the later bands, in raster order, down to
// the last row its voxels reach, updating only its own voxels: another band's
// voxel costs one test per span, not per pixel. So every voxel takes its pixels
// in pixel order, whatever the number of bands (one band: its own spans, with
// no remap). A voxel that needs a new record gets a temporary one from its task;
// the temporaries join the pools after the pass, in slot order.
//
// Runs: consecutive pixels of one voxel with the same class (instance) add
// their scores to the same histogram entry. The entry, the histogram's sum and
// the stuff sum are then accumulated in registers - the same float additions in
// the same order as one add() per pixel - and the entry is moved to its sorted
// place once at the end of the run, which is where per-pixel sorting would have
// left it (the other entries do not change during the run). Float weights
// then do not depend on where a run ends, so a voxel's runs go on across its
// rows (parked in its slot record meanwhile); quantised ones round once per
// run, so runs end at every voxel change, where the one-band walk's do.
#include <algorithm>
#include <cstring>
#include <type_traits>

#include "frame_pixels.h"
#include "histogram_run_kernels.h"
#include "map_scratch.h"

namespace pndt
{
namespace
{
/// Starts a run of updates of `id` with its first score: on id's entry (the
/// run holds its weight plus the score, one update left for the flush to
/// count), or as a new entry through add() (which may replace the smallest;
/// the update is counted at once, and 1 returned for the frame's total).
/// Always inlined: as a call it takes the run's variables by address, which
/// keeps them in memory (not registers) for the whole pixel loop.
template <typename H, typename Id>
[[gnu::always_inline]] inline uint32_t startRun(H& h, Id id, float score, uint32_t& updates, int& run_i, float& run_w,
                                            uint32_t& run_n)
{
    run_i = h.indexOf(id);
    if (run_i >= 0)
    {
        run_w = h.weight(run_i) + score;
        run_n = 1;
        return 0;
    }
    h.add(id, score);
    ++updates;
    run_i = h.indexOf(id);
    run_w = h.weight(run_i);
    run_n = 0;
    return 1;
}

/// A pixel within the current run (or without an update): its score is added
/// if it is an update, +0 otherwise, without a branch. An update here is one
/// of the run's (take implies the pixel's id is the run's): the frame's totals
/// count them from run_n at the flush.
inline void continueRun(bool take, float score, float& run_w, uint32_t& run_n)
{
    // take ? score : +0 by masking the bits: compilers turned the select into a
    // branch, which noisy scores near the threshold mispredict (a third of the
    // histogram pass on network-like labels).
    uint32_t bits;
    std::memcpy(&bits, &score, sizeof bits);
    bits &= 0u - uint32_t(take);
    float masked;
    std::memcpy(&masked, &bits, sizeof masked);
    run_w += masked;
    run_n += take;
}

}  // namespace

void PanopticMap::updateHistograms(const FramePixels& f, FrameStats& st)
{
    Scratch& s = *scratch_;
    const uint32_t nh = s.hitCount();
    const HitSlot* hits = s.hits();
    const int tasks = s.band_count;  // one per projection band: its home voxels
    if (s.hist_workers.size() < size_t(tasks)) s.hist_workers.resize(size_t(tasks));
    // Sized here, set by each task for its own voxels.
    if (s.new_label.size() < nh) s.new_label.resize(nh);
    if (s.new_instance.size() < nh) s.new_instance.resize(nh);
    if (s.slot_records.size() < nh) s.slot_records.resize(nh);

    if (tasks > 1)
        s.pool->run(tasks, [&](int t) { histogramTask(f, t); });
    else
        histogramTask(f, 0);

    // The new records join the pools in slot order: a task's voxels are a
    // contiguous range of slots, so its records follow those of the tasks
    // before it, and each task numbers and copies its own.
    s.new_record_base.resize(2 * (size_t(tasks) + 1));
    uint32_t* label_base = &s.new_record_base[0];
    uint32_t* instance_base = &s.new_record_base[size_t(tasks) + 1];
    label_base[0] = 0;
    instance_base[0] = 0;
    for (int t = 0; t < tasks; ++t)
    {
        label_base[t + 1] = label_base[t] + uint32_t(s.hist_workers[size_t(t)].labels.size());
        instance_base[t + 1] = instance_base[t] + uint32_t(s.hist_workers[size_t(t)].instances.size());
    }
    const uint32_t first_label = uint32_t(labels_.size()), first_instance = uint32_t(instance_records_.size());
    labels_.appendUnwritten(label_base[tasks]);
    instance_records_.appendUnwritten(instance_base[tasks]);
    const auto join = [&](int t) {
        const HistogramWorker& w = s.hist_workers[size_t(t)];
        uint32_t next_label = first_label + label_base[t], next_instance = first_instance + instance_base[t];
        for (uint32_t h = s.bands[size_t(t)].home_begin; h < s.bands[size_t(t)].home_end; ++h)
        {
            const uint32_t nl = s.new_label[h], ni = s.new_instance[h];
            if (nl == kNoRecord && ni == kNoRecord) continue;
            SurfaceRecord& sr = surfaces_[store_[hits[h].voxel].surface];
            if (nl != kNoRecord)
            {
                sr.labels = next_label++;
                labels_[sr.labels] = w.labels[nl];
            }
            if (ni != kNoRecord)
            {
                labels_[sr.labels].instances = next_instance;
                instance_records_[next_instance++] = w.instances[ni];
            }
        }
    };
    if (tasks > 1)
        s.pool->run(tasks, join);
    else
        join(0);
    // Classes beyond full records (semantic_eviction = false), task by task: each
    // voxel's pixels in pixel order, whatever the number of tasks.
    for (int t = 0; t < tasks; ++t)
        for (const HistogramWorker::SpilledPixel& p : s.hist_workers[size_t(t)].spilled)
        {
            const uint32_t li = surfaces_[store_[hits[p.slot].voxel].surface].labels;
            spills_.add(li, labels_[li], p.cls, p.score);
        }
    for (int t = 0; t < tasks; ++t)
    {
        st.semantic_updates += s.hist_workers[size_t(t)].semantic_updates;
        st.instance_updates += s.hist_workers[size_t(t)].instance_updates;
    }
}

void PanopticMap::histogramTask(const FramePixels& f, int task)
{
    Scratch& s = *scratch_;
    HistogramWorker& w = s.hist_workers[size_t(task)];
    const ProjectionBand& band = s.bands[size_t(task)];
    const uint32_t home_begin = band.home_begin, home_end = band.home_end;
    w.labels.clear();
    w.instances.clear();
    w.spilled.clear();
    std::fill(s.new_label.begin() + home_begin, s.new_label.begin() + home_end, kNoRecord);
    std::fill(s.new_instance.begin() + home_begin, s.new_instance.begin() + home_end, kNoRecord);
    // Every home voxel has pixels in the walk: its records are looked up here,
    // in slot order with the record chains prefetched ahead, instead of at its
    // first pixel, where four dependent cache misses stalled the walk (~15 % of
    // the pass's samples at 5 cm on a Zen 3).
    const HitSlot* const hits = s.hits();
    for (uint32_t h = home_begin; h < home_end; ++h)
    {
        prefetchRecordChain(hits, h, home_end);
        SlotRecords& r = s.slot_records[h];
        r = SlotRecords{};
        const uint32_t li = surfaces_[store_[hits[h].voxel].surface].labels;
        r.label = li != kNoRecord ? &labels_[li] : nullptr;
        r.instance = r.label && r.label->instances != kNoRecord ? &instance_records_[r.label->instances] : nullptr;
    }
    // No reallocation during the pass: records are held by pointer.
    if (w.labels.capacity() < home_end - home_begin) w.labels.reserve(home_end - home_begin);
    if (w.instances.capacity() < home_end - home_begin) w.instances.reserve(home_end - home_begin);

    // The band's spans, and on through the later bands' spans until the last
    // row its voxels reach.
    const int W = f.depth.width, H = f.depth.height;
    const uint32_t i_end = uint32_t(size_t(band.home_last_row + 1) * W);
    const int last_band = s.bandOfRow(band.home_last_row, H);
    const bool instances = f.hasInstances();
    const float theta_l = float(options_.theta_l), theta_z = float(options_.theta_z);
    const uint16_t void_id = options_.void_bin ? kVoidBin : 0;  // 0: void pixels leave h^L alone
    const bool spill = !options_.semantic_eviction;
    const uint16_t* sem = f.semantic.data.data();
    const float* sem_score = f.semantic_score.data.data();
    const int32_t* predicted = instances ? s.pixel_predicted.data() : nullptr;
    const uint32_t* decision = s.predicted_decision.data();  // per band: w.band_decision
    // Pixels of a merged prediction that lie on a map instance of another class.
    const uint32_t* split_stamp = s.split_pixels ? s.split_stamp.data() : nullptr;
    const uint32_t* split_id = s.split_id.data();
    const uint32_t split_now = s.split_counter;
    const float* pan_score = instances ? f.panoptic_score.data.data() : nullptr;
    SlotRecords* slot_records = s.slot_records.data();
    uint64_t semantic_updates = 0, instance_updates = 0;

    int32_t cur = -1;
    SlotRecords* cur_records = nullptr;
    LabelRecord* rec = nullptr;     // of the current voxel, or nullptr before its first update
    InstanceRecord* inst = nullptr;
    // Current semantic run: class, entry index and the accumulated floats.
    uint8_t run_l = 0;
    int run_li = 0;
    float run_lw = 0;
    uint32_t run_nl = 0;
    // Current instance run.
    uint32_t run_z = 0;
    int run_zi = 0;
    float run_zw = 0;
    uint32_t run_nz = 0;

    const auto flushSemantic = [&] {
        if (run_l == 0) return;
        rec->semantic.setWeight(run_li, run_lw);
        rec->n_l += run_nl;
        semantic_updates += run_nl;
        rec->semantic.bubbleUp(run_li);
        run_l = 0;
    };
    const auto flushInstance = [&] {
        if (run_z == 0) return;
        inst->hist.setWeight(run_zi, run_zw);
        inst->n_z += run_nz;
        instance_updates += run_nz;
        inst->hist.bubbleUp(run_zi);
        run_z = 0;
    };
    const auto labelRecord = [&]() -> LabelRecord& {
        if (!rec)
        {
            s.new_label[size_t(cur)] = uint32_t(w.labels.size());
            w.labels.emplace_back();
            rec = &w.labels.back();
            cur_records->label = rec;
        }
        return *rec;
    };

    // Spans and pixels hold their band's local slot and predicted index:
    // translated with the remaps of their band (identity for band 0), the
    // predicted indices through `decision` (set per band below).
    // Float weights: a voxel's runs wait in its slot record while the pass is elsewhere
    // (continued when the next row comes back to it, flushed at the end); quantised ones
    // round at each flush, so their runs end at every voxel change, as the one-band walk's.
    const auto parkRuns = [&] {
        if (!cur_records) return;
        SlotRecords& r = *cur_records;
        r.run_l = run_l;
        r.run_li = int8_t(run_li);
        r.run_lw = run_lw;
        r.run_nl = run_nl;
        r.run_z = run_z;
        r.run_zi = int8_t(run_zi);
        r.run_zw = run_zw;
        r.run_nz = run_nz;
    };
    const auto resumeRuns = [&](const SlotRecords& r) {
        run_l = r.run_l;
        run_li = r.run_li;
        run_lw = r.run_lw;
        run_nl = r.run_nl;
        run_z = r.run_z;
        run_zi = r.run_zi;
        run_zw = r.run_zw;
        run_nz = r.run_nz;
    };
    // The voxel of frame slot `slot` becomes the current one.
    const auto enter = [&](uint32_t slot) {
        if constexpr (kQuantisedHistograms)
        {
            flushSemantic();
            flushInstance();
        }
        else
            parkRuns();
        cur = int32_t(slot);
        cur_records = &slot_records[slot];
        if constexpr (!kQuantisedHistograms) resumeRuns(*cur_records);
        rec = cur_records->label;
        inst = cur_records->instance;
    };
    // One pixel of the current voxel.
    // `Walk`: a type per walk (one band, bands), so that each walk has its own
    // copy to inline (one copy called from both was not inlined: 1.5x slower).
    const auto update = [&](uint32_t i, auto /*Walk*/) {
        if (instances)
        {
            const int32_t p = predicted[i];
            const uint32_t z = split_stamp && split_stamp[i] == split_now ? split_id[i]
                               : p >= 0 ? decision[size_t(p)]
                                        : 0;
            const float sp = pan_score[i];
            // Scores near the threshold make "is it an update" unpredictable:
            // the common cases take no branch (adding +0 leaves a weight as it is).
            const bool take = (z != 0) & (sp > theta_z);
            if (!(take & (z != run_z)))
                continueRun(take, sp, run_zw, run_nz);
            else
            {
                flushInstance();
                labelRecord();  // the label record links the instance record
                if (!inst)
                {
                    s.new_instance[size_t(cur)] = uint32_t(w.instances.size());
                    w.instances.emplace_back();
                    inst = &w.instances.back();
                    cur_records->instance = inst;
                }
                instance_updates += startRun(inst->hist, z, sp, inst->n_z, run_zi, run_zw, run_nz);
                run_z = z;
            }
        }

        const uint16_t L = sem[i] ? sem[i] : void_id;
        const float sl = sem_score[i];
        const bool take = (L != 0) & (sl > theta_l);
        if (!(take & (L != run_l)))
            continueRun(take, sl, run_lw, run_nl);
        else
        {
            flushSemantic();
            LabelRecord& r = labelRecord();
            if (spill && r.semantic.size() == LabelRecord::kSemanticCapacity && r.semantic.indexOf(uint8_t(L)) < 0)
            {
                // A ninth class: no eviction, it waits for the spill (no run).
                w.spilled.push_back({uint32_t(cur), uint8_t(L), sl});
                ++r.n_l;
                ++semantic_updates;
            }
            else
            {
                semantic_updates += startRun(r.semantic, uint8_t(L), sl, r.n_l, run_li, run_lw, run_nl);
                run_l = uint8_t(L);
            }
        }
    };
    // Where the CPU has a block test, a span of a block (16 or 8 pixels) or
    // more starts with it: pixels that only continue the runs go a block a
    // step; after the first pixel that does not, the span goes on pixel by
    // pixel (runs that break every few pixels would waste block after block).
    const ContinueRuns continueRuns = bestContinueRuns();
    RunBlockInputs in;
    in.semantic = sem;
    in.semantic_score = sem_score;
    in.predicted = predicted;
    in.decision = decision;
    in.split_stamp = split_stamp;
    in.split_id = split_id;
    in.split_now = split_now;
    in.panoptic_score = pan_score;
    in.theta_l = theta_l;
    in.theta_z = theta_z;
    in.void_id = void_id;
    const auto walkSpan = [&](const PixelSpan& span, auto walk) {
        uint32_t i = span.begin;
        if (continueRuns.fn && span.end - i >= continueRuns.block)
        {
            RunSums sums{run_z, run_l, run_zw, run_lw, run_nz, run_nl};
            i = continueRuns.fn(in, i, span.end, sums);
            run_zw = sums.z_weight;
            run_lw = sums.l_weight;
            run_nz = sums.z_updates;
            run_nl = sums.l_updates;
        }
        for (; i < span.end; ++i) update(i, walk);
    };
    if (s.band_count == 1)
    {
        // One band (one thread): its spans in raster order, no translation.
        for (const PixelSpan& span : s.bands[0].spans)
        {
            if (int32_t(span.slot) != cur) enter(span.slot);
            walkSpan(span, std::false_type{});
        }
    }
    else
    {
        // The task's band and the later ones its voxels reach.
        for (int b = task; b <= last_band; ++b)
        {
            const ProjectionBand& pb = s.bands[size_t(b)];
            const uint32_t* slot_of = pb.remap.data();
            if (instances)
            {
                // The band's pixels hold its local predicted indices: their
                // decisions, translated once per band, so that the block test and
                // the pixel loop read decision[p] directly.
                const std::vector<int32_t>& remap = s.predicted_bands[size_t(b)].remap;
                w.band_decision.resize(remap.size());
                for (size_t j = 0; j < remap.size(); ++j) w.band_decision[j] = s.predicted_decision[size_t(remap[j])];
                decision = w.band_decision.data();
                in.decision = decision;
            }
            for (const PixelSpan& span : pb.spans)
            {
                if (span.begin >= i_end) break;
                const uint32_t slot = slot_of[span.slot];
                if (slot < home_begin || slot >= home_end)  // another band's voxel
                {
                    // Quantised weights round at each flush: end the runs where
                    // the one-band walk would (it enters that voxel), so every
                    // thread count stores the same bits.
                    if constexpr (kQuantisedHistograms)
                        if (cur >= 0)
                        {
                            flushSemantic();
                            flushInstance();
                            cur = -1;
                        }
                    continue;
                }
                if (int32_t(slot) != cur) enter(slot);
                walkSpan(span, std::true_type{});
            }
        }
    }
    flushSemantic();
    flushInstance();
    if constexpr (!kQuantisedHistograms)
    {
        // The runs parked in the task's other voxels.
        if (cur_records)
        {
            cur_records->run_l = 0;
            cur_records->run_z = 0;
        }
        for (uint32_t h = home_begin; h < home_end; ++h)
        {
            SlotRecords& r = slot_records[h];
            if (!r.run_l && !r.run_z) continue;
            resumeRuns(r);
            rec = r.label;
            inst = r.instance;
            flushSemantic();
            flushInstance();
        }
    }
    w.semantic_updates = semantic_updates;
    w.instance_updates = instance_updates;
}

}  // namespace pndt
