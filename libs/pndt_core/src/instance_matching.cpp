// Paper steps 3-4: back-project the map's thing voxels into the image as
// per-instance masks (vtou, projected NDT Gaussians, depth-tested) and match
// the predicted instances to them by IoU.
#include <pndt/instance_assignment.h>
#include <pndt/instance_rules.h>

#include <algorithm>
#include <cmath>

#include "candidate_sort.h"
#include "frame_pixels.h"
#include "map_scratch.h"
#include "mask_row_kernels.h"
#include "predicted_pixels.h"

namespace pndt
{
namespace
{
/// Sets the bits of pixels [a, b) (a < b) and returns how many were clear.
inline uint32_t markSpan(uint64_t* bits, uint32_t a, uint32_t b)
{
    const uint32_t wa = a >> 6, wb = (b - 1) >> 6;
    const uint64_t first = ~uint64_t(0) << (a & 63), last = ~uint64_t(0) >> (63 - ((b - 1) & 63));
    if (wa == wb)
    {
        const uint64_t m = first & last;
        const uint32_t fresh = uint32_t(__builtin_popcountll(m & ~bits[wa]));
        bits[wa] |= m;
        return fresh;
    }
    uint32_t fresh = uint32_t(__builtin_popcountll(first & ~bits[wa]));
    bits[wa] |= first;
    for (uint32_t w = wa + 1; w < wb; ++w)
    {
        fresh += uint32_t(__builtin_popcountll(~bits[w]));
        bits[w] = ~uint64_t(0);
    }
    fresh += uint32_t(__builtin_popcountll(last & ~bits[wb]));
    bits[wb] |= last;
    return fresh;
}

/// markSpan over spans [sp, end): each span's fresh pixels counted into inter[its prediction];
/// returns them all.
[[gnu::always_inline]] inline uint64_t markSpansImpl(uint64_t* bits, const MaskSpan* sp, const MaskSpan* end,
                                                     uint64_t* inter)
{
    uint64_t area = 0;
    for (; sp < end; ++sp)
    {
        const uint32_t fresh = markSpan(bits, sp->begin, sp->end);
        area += fresh;
        inter[sp->predicted] += fresh;
    }
    return area;
}
using MarkSpansFn = uint64_t (*)(uint64_t*, const MaskSpan*, const MaskSpan*, uint64_t*);
uint64_t markSpansPortable(uint64_t* bits, const MaskSpan* sp, const MaskSpan* end, uint64_t* inter)
{
    return markSpansImpl(bits, sp, end, inter);
}
#if defined(__x86_64__) && defined(__GNUC__)
// The baseline x86-64 build has no popcnt instruction: the bit counts were calls into libgcc's
// software popcount (8 % of matching's samples at 10 cm). Every CPU with AVX2 has popcnt.
[[gnu::target("popcnt")]] uint64_t markSpansPopcnt(uint64_t* bits, const MaskSpan* sp, const MaskSpan* end,
                                                   uint64_t* inter)
{
    return markSpansImpl(bits, sp, end, inter);
}
MarkSpansFn bestMarkSpans()
{
    static const bool popcnt = __builtin_cpu_supports("popcnt");
    return popcnt && simdCap() != SimdCap::Scalar ? markSpansPopcnt : markSpansPortable;
}
#else
MarkSpansFn bestMarkSpans() { return markSpansPortable; }
#endif
}  // namespace

namespace
{
/// The spans [sp, end) of a thing voxel (raster order, footprint `fp`) that lie in image
/// rows [row_begin, row_end) of W pixels.
std::pair<const MaskSpan*, const MaskSpan*> spansInRows(const MaskSpan* sp, const MaskSpan* end,
                                                        const MaskFootprint& fp, int row_begin, int row_end, int W)
{
    if (std::max(fp.r0, row_begin) >= std::min(fp.r1 + 1, row_end)) return {sp, sp};
    const auto before = [](const MaskSpan& x, uint32_t i) { return x.begin < i; };
    if (fp.r0 < row_begin) sp = std::lower_bound(sp, end, uint32_t(row_begin) * uint32_t(W), before);
    if (fp.r1 >= row_end) end = std::lower_bound(sp, end, uint32_t(row_end) * uint32_t(W), before);
    return {sp, end};
}
}  // namespace

void PanopticMap::predictedBand(const FramePixels& f, int band, int bands)
{
    Scratch& s = *scratch_;
    const int W = f.depth.width, H = f.depth.height;
    const size_t i0 = size_t(H * band / bands) * W, i1 = size_t(H * (band + 1) / bands) * W;
    assignPredicted(f.instance.data.data(), f.hasLabels() ? f.semantic.data.data() : nullptr, s.pixel_slot.data(),
                    s.pixel_predicted.data(), i0, i1, s.predicted_bands[size_t(band)], bestContinueInstance());
}

void PanopticMap::prefetchRecordChain(const HitSlot* hits, uint32_t h, uint32_t end) const
{
    // Each stage reads what an earlier iteration's prefetch brought in: a voxel's
    // records are four dependent reads (voxel, surface, labels, instances) into
    // pools of megabytes at 5 cm, in no order the hardware could guess.
    if (h + 12 < end) __builtin_prefetch(&store_[hits[h + 12].voxel]);
    if (h + 8 < end)
        if (const Voxel& v = store_[hits[h + 8].voxel]; v.surface != kNoRecord) __builtin_prefetch(&surfaces_[v.surface]);
    if (h + 4 < end)
        if (const Voxel& v = store_[hits[h + 4].voxel]; v.surface != kNoRecord)
            if (const uint32_t l = surfaces_[v.surface].labels; l != kNoRecord) __builtin_prefetch(&labels_[l]);
    if (h + 2 < end)
        if (const LabelRecord* rec = labelsOf(store_[hits[h + 2].voxel]); rec && rec->instances != kNoRecord)
        {
            const char* z = reinterpret_cast<const char*>(&instance_records_[rec->instances]);
            for (size_t b = 0; b < sizeof(InstanceRecord); b += 64) __builtin_prefetch(z + b);
        }
}

void PanopticMap::matchInstances(const FramePixels& f, const Pose& T, FrameStats& st)
{
    Scratch& s = *scratch_;
    const size_t N = f.depth.data.size();
    const int threads = s.pool ? s.threads : 1;
    // This frame's per-instance state starts empty: a frame that returns early
    // (no prediction) must not leave the previous frame's split pixels or map
    // instance classes to the histogram pass.
    s.split_pixels = false;
    s.group_class.clear();

    // Predicted instances, counted on pixels that were mapped (valid depth): row
    // bands with their own tables, merged in band order (first occurrence).
    s.pixel_predicted.resize(N);
    const int B = s.band_count;  // the projection's bands: one row-to-band rule for both
    if (s.predicted_bands.size() < size_t(B)) s.predicted_bands.resize(size_t(B));
    if (B > 1)
        s.pool->run(B, [&](int b) { predictedBand(f, b, B); });
    else
        predictedBand(f, 0, 1);
    // Merged into band 0 in band order (first occurrence). Pixels keep their
    // band's local index; readers translate with the band's remap.
    PredictedBand& g = s.predicted_bands[0];
    g.remap.resize(g.ids.size());
    for (size_t j = 0; j < g.ids.size(); ++j) g.remap[j] = int32_t(j);
    for (int b = 1; b < B; ++b)
    {
        PredictedBand& pb = s.predicted_bands[size_t(b)];
        pb.remap.resize(pb.ids.size());
        for (size_t j = 0; j < pb.ids.size(); ++j)
        {
            const auto [it, inserted] = g.index.try_emplace(pb.ids[j], uint32_t(g.ids.size()));
            if (inserted)
            {
                g.ids.push_back(pb.ids[j]);
                g.area.push_back(0);
                g.cls.push_back(pb.cls[j]);
            }
            g.area[it->second] += pb.area[j];
            pb.remap[j] = int32_t(it->second);
        }
    }
    const size_t P = g.ids.size();
    st.predicted_instances = P;
    s.predicted_decision.assign(P, 0);
    if (P == 0) return;

    // Candidate voxels: thing voxels seen in this frame, once per top-z instance,
    // sorted by (instance, voxel). Each task sorts the pairs of its share of the
    // frame's voxels; the sorted shares are then merged (the pairs are unique, so
    // the result does not depend on the shares). Each thing voxel is numbered
    // once (in slot order), for its footprint and pixels.
    const uint32_t nh = s.hitCount();
    const int parts = threads > 1 && nh >= 256 ? 4 * threads : 1;
    if (s.candidate_parts.size() < size_t(parts)) s.candidate_parts.resize(size_t(parts));
    if (s.thing_parts.size() < size_t(parts)) s.thing_parts.resize(size_t(parts));
    if (s.candidate_sort_tmp.size() < size_t(parts)) s.candidate_sort_tmp.resize(size_t(parts));
    const auto collect = [&](int t) {
        auto& part = s.candidate_parts[size_t(t)];
        auto& things = s.thing_parts[size_t(t)];
        part.clear();
        things.clear();
        const HitSlot* hits = s.hits();
        const uint32_t h0 = uint32_t(uint64_t(nh) * t / parts), e = uint32_t(uint64_t(nh) * (t + 1) / parts);
        for (uint32_t h = h0; h < e; ++h)
        {
            prefetchRecordChain(hits, h, e);
            const uint32_t vi = hits[h].voxel;
            const Voxel& v = store_[vi];
            if (!isOccupied(v)) continue;
            const LabelRecord* rec = labelsOf(v);
            if (!rec || rec->instances == kNoRecord || !isThing(*rec, options_.classes, options_.theta_st, spillOf(v)))
                continue;
            const auto& hist = instance_records_[rec->instances].hist;
            const uint32_t thing = uint32_t(things.size());
            bool any = false;
            for (int j = 0, n = hist.size(); j < n; ++j)
                if (isInTopZ(hist, hist.ids[j], options_.theta_b))
                {
                    part.push_back({hist.ids[j], vi, thing});
                    any = true;
                }
            if (any) things.push_back(vi);
        }
        sortCandidates(part, s.candidate_sort_tmp[size_t(t)]);
    };
    if (parts > 1)
        s.pool->run(parts, collect);
    else
        collect(0);
    s.thing_base.resize(size_t(parts) + 1);
    s.thing_base[0] = 0;
    for (int t = 0; t < parts; ++t) s.thing_base[size_t(t) + 1] = s.thing_base[size_t(t)] + uint32_t(s.thing_parts[size_t(t)].size());
    s.thing_voxel.resize(s.thing_base[size_t(parts)]);
    // Each share's thing voxels and numbers joined, then the sorted shares
    // merged in pairs, level by level, each level's merges in parallel.
    const auto join = [&](int t) {
        std::copy(s.thing_parts[size_t(t)].begin(), s.thing_parts[size_t(t)].end(),
                  s.thing_voxel.begin() + s.thing_base[size_t(t)]);
        for (MaskCandidate& c : s.candidate_parts[size_t(t)]) c.thing += s.thing_base[size_t(t)];
    };
    if (parts > 1)
        s.pool->run(parts, join);
    else
        join(0);
    // Levels go from the shares to two sets of merge buffers in turn, the last
    // into the candidates: no buffer changes hands, so each keeps its capacity
    // (a share does: the sort may swap it with its scratch).
    if (parts == 1) s.candidates.swap(s.candidate_parts[0]);
    if (s.candidate_merge.size() < 2 * size_t(parts)) s.candidate_merge.resize(2 * size_t(parts));
    std::vector<MaskCandidate>*from = s.candidate_parts.data(), *to = s.candidate_merge.data();
    std::vector<MaskCandidate>* spare = to + parts;
    for (int w = 1; w < parts; w *= 2)
    {
        const bool last = 2 * w >= parts;
        const auto mergePair = [&](int m) {
            const size_t a = size_t(2 * w * m), b = a + size_t(w);
            std::vector<MaskCandidate>& out = last ? s.candidates : to[a];
            if (b >= size_t(parts))
            {
                out.assign(from[a].begin(), from[a].end());  // no partner at this level
                return;
            }
            out.resize(from[a].size() + from[b].size());
            std::merge(from[a].begin(), from[a].end(), from[b].begin(), from[b].end(), out.begin());
        };
        const int merges = (parts + 2 * w - 1) / (2 * w);
        if (merges > 1)
            s.pool->run(merges, mergePair);
        else
            mergePair(0);
        from = to;
        std::swap(to, spare);
    }
    s.groups.clear();
    for (size_t a = 0; a < s.candidates.size();)
    {
        size_t b = a;
        while (b < s.candidates.size() && s.candidates[b].first == s.candidates[a].first) ++b;
        s.groups.push_back({a, b});
        a = b;
    }

    // vtou of each thing voxel, once however many instances it has: its
    // footprint, then its pixels that pass the depth test (in raster order),
    // as row spans in one buffer (the footprints' boxes bound them).
    const size_t G = s.groups.size();
    const size_t TV = s.thing_voxel.size();
    const Pose T_cam_world = T.inverse();
    s.footprints.resize(TV);
    s.thing_spans.resize(TV + 1);
    s.thing_span_count.resize(TV);
    const int thing_tasks = threads > 1 && TV >= 128 ? 4 * threads : 1;
    s.mask_footprint = bestMaskFootprint();
    const int H_rows = f.depth.height;
    s.row_remap.resize(size_t(H_rows));
    for (int r = 0; r < H_rows; ++r)
        s.row_remap[size_t(r)] = s.predicted_bands[size_t(s.bandOfRow(r, H_rows))].remap.data();
    const auto footprints = [&](int t) {
        for (size_t u = TV * size_t(t) / size_t(thing_tasks), e = TV * size_t(t + 1) / size_t(thing_tasks); u < e; ++u)
        {
            const MaskFootprint fp = maskFootprint(s.thing_voxel[u], T_cam_world, f.K);
            s.footprints[u] = fp;
            s.thing_spans[u + 1] =
                fp.r0 <= fp.r1 && fp.c0 <= fp.c1 ? uint64_t(fp.r1 - fp.r0 + 1) * uint64_t(fp.c1 - fp.c0 + 1) : 0;
        }
    };
    if (thing_tasks > 1)
        s.pool->run(thing_tasks, footprints);
    else
        footprints(0);
    s.thing_spans[0] = 0;
    for (size_t u = 0; u < TV; ++u) s.thing_spans[u + 1] += s.thing_spans[u];
    s.mask_spans.reserve(size_t(s.thing_spans[TV]));
    // Each task's voxels write their spans one after the other from the start of
    // the task's share of the buffer (the bound above), so that the buffer is
    // written and read in order. (At its place in the box-area bound, each voxel's
    // first spans were a cache miss for the writer and for every reader.)
    const auto rasterise = [&](int t) {
        const size_t u0 = TV * size_t(t) / size_t(thing_tasks), e = TV * size_t(t + 1) / size_t(thing_tasks);
        uint64_t at = s.thing_spans[u0];  // read before this task moves it (no other task writes it)
        for (size_t u = u0; u < e; ++u)
        {
            if (u + 1 < e) prefetchFootprint(s.footprints[u + 1], f);
            s.thing_spans[u] = at;
            s.thing_span_count[u] = footprintSpans(s.footprints[u], f, s.mask_spans.data() + at);
            at += s.thing_span_count[u];
        }
    };
    if (thing_tasks > 1)
        s.pool->run(thing_tasks, rasterise);
    else
        rasterise(0);

    // One mask per map instance: the union of its voxels' pixels. A mask with
    // a large share of the frame's spans is cut into the image's row bands, so
    // that it does not leave a thread alone at the end: a pixel lies in one
    // band, so each piece dedupes its own pixels (per-thread pixel bits) and the
    // pieces' counts add up (per-thread sums). Smaller masks stay whole: every
    // piece walks all of its mask's voxels, which for a mask of a few rows is
    // most of the work. Most spans first.
    const int W = f.depth.width, H = f.depth.height;
    const size_t P1 = P + 1;  // per group: pixels of no prediction, then each prediction
    if (s.mask_workers.size() < size_t(threads)) s.mask_workers.resize(size_t(threads));
    for (int t = 0; t < threads; ++t)
    {
        MaskWorker& m = s.mask_workers[size_t(t)];
        if (m.bits.size() != (N + 63) / 64) m.bits.assign((N + 63) / 64, 0);
        m.area.assign(G, 0);
        m.inter.assign(G * P1, 0);
    }
    s.group_spans.assign(G, 0);
    uint64_t all_spans = 0;
    for (size_t gi = 0; gi < G; ++gi)
    {
        for (size_t c = s.groups[gi].first; c < s.groups[gi].second; ++c)
            s.group_spans[gi] += s.thing_span_count[s.candidates[c].thing];
        all_spans += s.group_spans[gi];
    }
    s.mask_order.resize(G);
    for (size_t gi = 0; gi < G; ++gi) s.mask_order[gi] = uint32_t(gi);
    std::sort(s.mask_order.begin(), s.mask_order.end(), [&](uint32_t a, uint32_t b) {
        return s.group_spans[a] != s.group_spans[b] ? s.group_spans[a] > s.group_spans[b] : a < b;
    });
    s.mask_tasks.clear();
    for (const uint32_t gi : s.mask_order)
    {
        const bool cut = threads > 1 && s.group_spans[gi] * uint64_t(4 * threads) > all_spans;
        const int pieces = cut ? B : 1;
        for (int piece = 0; piece < pieces; ++piece) s.mask_tasks.push_back({gi, uint32_t(piece), uint32_t(pieces)});
    }
    const MarkSpansFn mark_spans = bestMarkSpans();
    const auto prefetchSpans = [&](uint32_t u) {
        const char* first = reinterpret_cast<const char*>(s.mask_spans.data() + s.thing_spans[u]);
        const size_t bytes = size_t(s.thing_span_count[u]) * sizeof(MaskSpan);
        for (size_t b = 0; b < std::min<size_t>(bytes, 4 * 64); b += 64) __builtin_prefetch(first + b);
    };
    const auto mask = [&](int task, int thread) {
        const MaskTask& mt = s.mask_tasks[size_t(task)];
        const size_t gi = mt.group;
        const int piece = int(mt.piece), pieces = int(mt.pieces);
        const int row_begin = H * piece / pieces, row_end = H * (piece + 1) / pieces;
        MaskWorker& m = s.mask_workers[size_t(thread)];
        uint64_t area = 0;
        uint64_t* inter = &m.inter[gi * P1 + 1];  // [-1] counts pixels of no prediction
        uint64_t* bits = m.bits.data();
        // The spans of thing voxel u in this piece's rows.
        const auto spans = [&](uint32_t u) -> std::pair<const MaskSpan*, const MaskSpan*> {
            const MaskSpan* sp = s.mask_spans.data() + s.thing_spans[u];
            const MaskSpan* end = sp + s.thing_span_count[u];
            if (pieces > 1) return spansInRows(sp, end, s.footprints[u], row_begin, row_end, W);
            return {sp, end};
        };
        // Pixels not in this mask yet: a word (64 pixels) at a time. The voxels come
        // in candidate order, not in the order their spans were cut: the next
        // voxels' spans are fetched ahead (their first read held half of this
        // loop's samples at 5 cm).
        const size_t c_end = s.groups[gi].second;
        for (size_t c = s.groups[gi].first; c < c_end; ++c)
        {
            if (c + 2 < c_end) prefetchSpans(s.candidates[c + 2].thing);
            const auto [sp, end] = spans(s.candidates[c].thing);
            area += mark_spans(bits, sp, end, inter);
        }
        // Clear the mask's bits for the next one: the words its spans touched.
        for (size_t c = s.groups[gi].first; c < s.groups[gi].second; ++c)
            for (auto [sp, end] = spans(s.candidates[c].thing); sp < end; ++sp)
                for (uint32_t w = sp->begin >> 6, we = (sp->end - 1) >> 6; w <= we; ++w) bits[w] = 0;
        m.area[gi] += area;
    };
    const int mask_tasks = int(s.mask_tasks.size());
    if (threads > 1 && mask_tasks > 1)
        s.pool->runWithThread(mask_tasks, mask);
    else
        for (int task = 0; task < mask_tasks; ++task) mask(task, 0);
    s.group_area.assign(G, 0);
    s.group_inter.assign(G * P, 0);
    for (int t = 0; t < threads; ++t)
    {
        const MaskWorker& m = s.mask_workers[size_t(t)];
        for (size_t gi = 0; gi < G; ++gi)
        {
            s.group_area[gi] += m.area[gi];
            for (size_t p = 0; p < P; ++p) s.group_inter[gi * P + p] += m.inter[gi * P1 + 1 + p];
        }
    }

    s.iou.resize(G * P);
    for (size_t gi = 0; gi < G; ++gi)
        for (size_t p = 0; p < P; ++p)
            s.iou[gi * P + p] = intersectionOverUnion(s.group_inter[gi * P + p], s.group_area[gi], g.area[p]);
    AssignmentInput in;
    in.iou = s.iou.data();
    in.class_of = f.hasLabels() ? g.cls.data() : nullptr;
    // The class of each map instance in view, for every rule that needs it.
    if (f.hasLabels() &&
        (options_.class_consistent_instances || options_.split_coverage > 0 || options_.fragment_merge_frames > 0))
    {
        classifyMapInstances();
        if (options_.class_consistent_instances) in.map_class = s.group_class.data();
    }
    in.map_instances = G;
    in.predictions = P;
    in.theta_m = options_.theta_m;
    in.theta_n = options_.theta_n;
    assignPredictions(in, s.assignment);
    for (size_t p = 0; p < P; ++p)
    {
        const int32_t a = s.assignment[p];
        if (a >= 0)
        {
            s.predicted_decision[p] = s.candidates[s.groups[size_t(a)].first].first;
            ++st.matched_instances;
        }
        else if (a == kAssignNew)
        {
            s.predicted_decision[p] = next_instance_id_++;
            ++st.new_instances;
        }
        else
            ++st.ambiguous_instances;
    }
    // Frames seen: once per map instance that a prediction took in this frame.
    for (size_t p = 0; p < P; ++p)
    {
        const uint32_t z = s.predicted_decision[p];
        bool first = z != 0;
        for (size_t q = 0; q < p && first; ++q) first = s.predicted_decision[q] != z;
        if (first) ++instance_frames_[z];
    }
    splitMergedPredictions(f, st);
    collectFragmentEvidence();
}

void PanopticMap::collectFragmentEvidence()
{
    Scratch& s = *scratch_;
    const size_t G = s.groups.size(), P = s.predicted_bands[0].ids.size();
    if (options_.fragment_merge_frames == 0 || s.group_class.size() != G || G < 2) return;
    const PredictedBand& g = s.predicted_bands[0];
    // Each map instance in view that one prediction of its class covers mostly.
    const uint64_t min_mask_pixels = options_.fragment_min_mask_pixels;  // smaller masks say little
    const double cover = options_.fragment_cover_share;
    s.coverer.assign(G, -1);
    for (size_t gi = 0; gi < G; ++gi)
    {
        if (s.group_class[gi] == 0 || s.group_area[gi] < min_mask_pixels) continue;
        for (size_t p = 0; p < P; ++p)
            if (g.cls[p] == s.group_class[gi] && double(s.group_inter[gi * P + p]) > cover * double(s.group_area[gi]))
                s.coverer[gi] = int32_t(p);
    }
    for (size_t a = 0; a < G; ++a)
    {
        if (s.coverer[a] < 0) continue;
        for (size_t b = a + 1; b < G; ++b)
        {
            if (s.coverer[b] < 0 || s.group_class[b] != s.group_class[a]) continue;
            uint32_t za = s.candidates[s.groups[a].first].first, zb = s.candidates[s.groups[b].first].first;
            if (za > zb) std::swap(za, zb);
            auto& e = s.pair_evidence[(uint64_t(za) << 32) | zb];
            if (s.coverer[a] == s.coverer[b])
                ++e.joint;
            else
                ++e.apart;
            if (e.joint >= options_.fragment_merge_frames &&
                double(e.joint) > options_.fragment_joint_factor * double(e.apart))
                s.fragment_merges.emplace_back(zb, za);  // keep the older id
        }
    }
}

void PanopticMap::mergeFragments(FrameStats& st)
{
    Scratch& s = *scratch_;
    if (s.fragment_merges.empty()) return;
    // Chains (c into b, b into a) end at the oldest id.
    tsl::robin_map<uint32_t, uint32_t> into;
    uint32_t first = UINT32_MAX, last = 0;  // the merged ids' range: records without one skip the lookups
    for (const auto& [from, to] : s.fragment_merges)
    {
        into[from] = to;
        first = std::min(first, from);
        last = std::max(last, from);
    }
    const auto root = [&](uint32_t z) {
        for (auto it = into.find(z); it != into.end(); it = into.find(z)) z = it->second;
        return z;
    };
    renameInstances(root, first, last);
    st.merged_fragments += into.size();
    // Evidence about a merged id now concerns its root: start those pairs afresh.
    const auto merged = [&](uint32_t z) { return z >= first && z <= last && into.count(z); };
    for (auto it = s.pair_evidence.begin(); it != s.pair_evidence.end();)
        if (merged(uint32_t(it->first >> 32)) || merged(uint32_t(it->first)))
            it = s.pair_evidence.erase(it);
        else
            ++it;
    s.fragment_merges.clear();
}

void PanopticMap::classifyMapInstances()
{
    Scratch& s = *scratch_;
    const size_t G = s.groups.size(), C = s.candidates.size();
    // Class of each map instance: the thing class with the most semantic mass over
    // its voxels in view (the propagation rule, on what the frame sees). Groups
    // are independent: tasks take groups by their first candidate, so that each
    // does about as many voxels (one instance may hold most of them).
    const ClassSet& classes = options_.classes;
    s.group_class.assign(G, 0);
    const int tasks = s.pool && C >= 1024 ? 4 * s.threads : 1;
    if (s.class_mass.size() < size_t(tasks)) s.class_mass.resize(size_t(tasks));
    const auto classify = [&](int t) {
        std::vector<float>& mass = s.class_mass[size_t(t)];
        mass.resize(classes.size());
        const auto firstGroupFrom = [&](size_t c) {
            return size_t(std::partition_point(s.groups.begin(), s.groups.end(),
                                               [c](const std::pair<size_t, size_t>& g) { return g.first < c; }) -
                          s.groups.begin());
        };
        const size_t g_end = firstGroupFrom(C * size_t(t + 1) / size_t(tasks));
        for (size_t gi = firstGroupFrom(C * size_t(t) / size_t(tasks)); gi < g_end; ++gi)
        {
            std::fill(mass.begin(), mass.end(), 0.f);
            for (size_t c = s.groups[gi].first; c < s.groups[gi].second; ++c)
            {
                const Voxel& v = store_[s.candidates[c].second];
                addThingMass(*labelsOf(v), classes, mass.data(), spillOf(v));
            }
            const auto best = std::max_element(mass.begin(), mass.end());
            if (*best > 0) s.group_class[gi] = uint16_t(best - mass.begin());
        }
    };
    if (tasks > 1)
        s.pool->run(tasks, classify);
    else
        classify(0);
}

void PanopticMap::splitMergedPredictions(const FramePixels& f, FrameStats& st)
{
    Scratch& s = *scratch_;
    s.split_pixels = false;
    const size_t G = s.groups.size(), P = s.predicted_bands[0].ids.size();
    if (options_.split_coverage <= 0 || s.group_class.size() != G || G < 2) return;
    const PredictedBand& g = s.predicted_bands[0];
    const ClassSet& classes = options_.classes;

    const size_t N = f.depth.data.size();
    if (s.split_stamp.size() != N || s.split_counter == 0xFFFFFFFFu)
    {
        s.split_stamp.assign(N, 0);
        s.split_id.resize(N);
        s.split_counter = 0;
    }
    const uint32_t stamp = ++s.split_counter;
    // The splits, in (map instance, prediction) order: later ones overwrite
    // earlier ones' pixels.
    s.splits.clear();
    for (size_t gi = 0; gi < G; ++gi)
    {
        const uint16_t gc = s.group_class[gi];
        if (gc == 0 || s.group_area[gi] == 0) continue;
        for (size_t p = 0; p < P; ++p)
        {
            if (g.cls[p] == 0 || g.cls[p] == gc || s.assignment[p] == int32_t(gi)) continue;
            if (double(s.group_inter[gi * P + p]) < options_.split_coverage * double(s.group_area[gi])) continue;
            // p swallowed most of a map instance of another class: its pixels there
            // keep that instance, except on voxels that are of p's class themselves
            // (an early merge in the map that p now resolves).
            s.splits.push_back({uint32_t(gi), uint32_t(p)});
        }
    }
    if (s.splits.empty()) return;
    st.split_predictions += s.splits.size();
    s.split_pixels = true;
    const int threads = s.pool ? s.threads : 1;
    // Each candidate's own class, once (a voxel may be split by several
    // predictions), in parallel: four dependent reads per voxel.
    s.own_class.resize(s.candidates.size());
    const auto ownClasses = [&](size_t i_begin, size_t i_end) {
        for (size_t i = i_begin; i < i_end; ++i)
        {
            const uint32_t gi = s.splits[i].first;
            if (i > 0 && s.splits[i - 1].first == gi) continue;  // the group's voxels are done
            for (size_t c = s.groups[gi].first; c < s.groups[gi].second; ++c)
            {
                const Voxel& v = store_[s.candidates[c].second];
                s.own_class[c] = ownThingClass(*labelsOf(v), classes, spillOf(v));
            }
        }
    };
    const int class_tasks = threads > 1 && s.splits.size() > 1 ? std::min(4 * threads, int(s.splits.size())) : 1;
    if (class_tasks > 1)
        s.pool->run(class_tasks, [&](int t) {
            ownClasses(s.splits.size() * size_t(t) / size_t(class_tasks),
                       s.splits.size() * size_t(t + 1) / size_t(class_tasks));
        });
    else
        ownClasses(0, s.splits.size());
    // The pixels, in row bands: a pixel lies in one band, and within it the
    // splits write in the order above.
    const int W = f.depth.width, H = f.depth.height;
    const int bands = threads > 1 ? 4 * threads : 1;
    const auto band = [&](int b) {
        const int row_begin = H * b / bands, row_end = H * (b + 1) / bands;
        for (const auto& [gi, p] : s.splits)
        {
            const uint32_t z = s.candidates[s.groups[gi].first].first;
            for (size_t c = s.groups[gi].first; c < s.groups[gi].second; ++c)
            {
                if (s.own_class[c] == g.cls[p]) continue;
                const uint32_t u = s.candidates[c].thing;
                const MaskSpan* first = s.mask_spans.data() + s.thing_spans[u];
                auto [sp, end] = spansInRows(first, first + s.thing_span_count[u], s.footprints[u], row_begin,
                                             row_end, W);
                for (; sp < end; ++sp)
                    if (sp->predicted == int32_t(p))
                    {
                        // Two fills, not one loop over both arrays: that loop was not vectorised.
                        std::fill(s.split_stamp.begin() + sp->begin, s.split_stamp.begin() + sp->end, stamp);
                        std::fill(s.split_id.begin() + sp->begin, s.split_id.begin() + sp->end, z);
                    }
            }
        }
    };
    if (bands > 1)
        s.pool->run(bands, band);
    else
        band(0);
}

MaskFootprint PanopticMap::maskFootprint(uint32_t voxel, const Pose& T_cam_world, const CameraIntrinsics& K) const
{
    const Voxel& v = store_[voxel];
    if (options_.use_ndt && hasGaussian(v))
        return gaussianFootprint(gaussianOf(v), T_cam_world, K, options_.vtou_mahalanobis_sq);
    // Cube ablation (or too few samples): the projected voxel's bounding box.
    return cubeFootprint(grid_.minCorner(store_.key(voxel)), options_.voxel_size, T_cam_world, K);
}

void PanopticMap::prefetchFootprint(const MaskFootprint& fp, const FramePixels& f) const
{
    // The footprint's rows are 2.5 kB apart (640 pixels): the hardware does not
    // fetch them ahead, and the row kernel waited on them (a third of its time).
    const Scratch& s = *scratch_;
    const size_t W = size_t(f.depth.width);
    for (int r = fp.r0; r <= fp.r1; ++r)
    {
        const int32_t* predicted = s.pixel_predicted.data() + size_t(r) * W;
        const float* depth = f.depth.data.data() + size_t(r) * W;
        for (int c = fp.c0; c <= fp.c1; c += 16)  // a line each, and the row's last pixel's
        {
            __builtin_prefetch(predicted + c);
            __builtin_prefetch(depth + c);
        }
        __builtin_prefetch(predicted + fp.c1);
        __builtin_prefetch(depth + fp.c1);
    }
}

uint32_t PanopticMap::footprintSpans(const MaskFootprint& fp, const FramePixels& f, MaskSpan* out)
{
    Scratch& s = *scratch_;
    const double tol = options_.vtou_depth_tolerance * options_.voxel_size;
    const double k2 = options_.vtou_mahalanobis_sq;
    const DepthWindow window = depthWindow(fp.z0, tol);
    return s.mask_footprint(fp, k2, s.pixel_predicted.data(), f.depth.data.data(), f.depth.width, window,
                            s.row_remap.data(), out);
}

}  // namespace pndt
