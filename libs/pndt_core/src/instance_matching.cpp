// Paper steps 3-4: back-project the map's thing voxels into the image as
// per-instance masks (vtou, projected NDT Gaussians, depth-tested) and match
// the predicted instances to them by IoU.
#include <pndt/instance_assignment.h>
#include <pndt/instance_rules.h>

#include <algorithm>
#include <cmath>

#include "frame_pixels.h"
#include "map_scratch.h"
#include "predicted_pixels.h"

namespace pndt
{
void PanopticMap::predictedBand(const FramePixels& f, int band, int bands)
{
    Scratch& s = *scratch_;
    const int W = f.depth.width, H = f.depth.height;
    const size_t i0 = size_t(H * band / bands) * W, i1 = size_t(H * (band + 1) / bands) * W;
    assignPredicted(f.instance.data.data(), f.hasLabels() ? f.semantic.data.data() : nullptr, s.pixel_slot.data(),
                    s.pixel_predicted.data(), i0, i1, s.predicted_bands[size_t(band)], bestContinueInstance());
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
    // the result does not depend on the shares).
    const uint32_t nh = s.hitCount();
    const int parts = threads > 1 && nh >= 1024 ? 4 * threads : 1;
    if (s.candidate_parts.size() < size_t(parts)) s.candidate_parts.resize(size_t(parts));
    const auto collect = [&](int t) {
        auto& part = s.candidate_parts[size_t(t)];
        part.clear();
        const HitSlot* hits = s.hits();
        for (uint32_t h = uint32_t(uint64_t(nh) * t / parts), e = uint32_t(uint64_t(nh) * (t + 1) / parts); h < e; ++h)
        {
            const uint32_t vi = hits[h].voxel;
            const Voxel& v = store_[vi];
            if (!isOccupied(v)) continue;
            const LabelRecord* rec = labelsOf(v);
            if (!rec || rec->instances == kNoRecord || !isThing(*rec, options_.classes, options_.theta_st, spillOf(v)))
                continue;
            const auto& hist = instance_records_[rec->instances].hist;
            for (int j = 0, n = hist.size(); j < n; ++j)
                if (isInTopZ(hist, hist.ids[j], options_.theta_b)) part.emplace_back(hist.ids[j], vi);
        }
        std::sort(part.begin(), part.end());
    };
    if (parts > 1)
        s.pool->run(parts, collect);
    else
        collect(0);
    s.candidates.swap(s.candidate_parts[0]);
    for (int t = 1; t < parts; ++t)
    {
        const auto& part = s.candidate_parts[size_t(t)];
        s.candidate_merge.resize(s.candidates.size() + part.size());
        std::merge(s.candidates.begin(), s.candidates.end(), part.begin(), part.end(), s.candidate_merge.begin());
        s.candidates.swap(s.candidate_merge);
    }
    s.groups.clear();
    for (size_t a = 0; a < s.candidates.size();)
    {
        size_t b = a;
        while (b < s.candidates.size() && s.candidates[b].first == s.candidates[a].first) ++b;
        s.groups.push_back({a, b});
        a = b;
    }

    // One mask per map instance. Each mask is cut into the image's row bands,
    // so that a large one does not leave a thread alone at the end: a pixel
    // lies in one band, so each piece dedupes its own pixels (per-thread
    // stamps) and the pieces' counts add up (per-thread sums). Largest masks
    // first. The footprints of the candidate voxels are computed once.
    const size_t G = s.groups.size(), C = s.candidates.size();
    const Pose T_cam_world = T.inverse();
    s.footprints.resize(C);
    const auto footprints = [&](int t, int tasks) {
        for (size_t c = C * size_t(t) / size_t(tasks), e = C * size_t(t + 1) / size_t(tasks); c < e; ++c)
            s.footprints[c] = maskFootprint(s.candidates[c].second, T_cam_world, f.K);
    };
    const int footprint_tasks = threads > 1 && C >= 256 ? 4 * threads : 1;
    if (footprint_tasks > 1)
        s.pool->run(footprint_tasks, [&](int t) { footprints(t, footprint_tasks); });
    else
        footprints(0, 1);

    const int H = f.depth.height;
    const int pieces = threads > 1 ? B : 1;
    const int mask_tasks = int(G) * pieces;
    if (s.mask_workers.size() < size_t(threads)) s.mask_workers.resize(size_t(threads));
    for (int t = 0; t < threads; ++t)
    {
        MaskWorker& m = s.mask_workers[size_t(t)];
        // One stamp per task: this frame's must not wrap around to the stamps' 0.
        if (m.stamp.size() != N || m.counter > 0xFFFFFFFFu - uint32_t(mask_tasks))
        {
            m.stamp.assign(N, 0);
            m.counter = 0;
        }
        m.area.assign(G, 0);
        m.inter.assign(G * P, 0);
    }
    s.mask_order.resize(G);
    for (size_t gi = 0; gi < G; ++gi) s.mask_order[gi] = uint32_t(gi);
    const auto size = [&](uint32_t gi) { return s.groups[gi].second - s.groups[gi].first; };
    std::sort(s.mask_order.begin(), s.mask_order.end(),
              [&](uint32_t a, uint32_t b) { return size(a) != size(b) ? size(a) > size(b) : a < b; });
    const auto mask = [&](int task, int thread) {
        const size_t gi = s.mask_order[size_t(task / pieces)];
        const int piece = task % pieces, row_begin = H * piece / pieces, row_end = H * (piece + 1) / pieces;
        MaskWorker& m = s.mask_workers[size_t(thread)];
        const uint32_t stamp = ++m.counter;
        uint64_t area = 0;
        uint64_t* inter = &m.inter[gi * P];
        uint32_t* stamps = m.stamp.data();
        for (size_t c = s.groups[gi].first; c < s.groups[gi].second; ++c)
        {
            const MaskFootprint& fp = s.footprints[c];
            const int r0 = std::max(fp.r0, row_begin), r1 = std::min(fp.r1 + 1, row_end);
            if (r0 >= r1) continue;
            forEachFootprintPixel(fp, r0, r1, f, [&](size_t i, int32_t p) {
                if (stamps[i] == stamp) return;
                stamps[i] = stamp;
                ++area;
                if (p >= 0) ++inter[size_t(p)];
            });
        }
        m.area[gi] += area;
    };
    if (threads > 1 && mask_tasks > 1)
        s.pool->runWithThread(mask_tasks, mask);
    else
        for (int task = 0; task < mask_tasks; ++task) mask(task, 0);
    s.group_area.assign(G, 0);
    s.group_inter.assign(G * P, 0);
    for (int t = 0; t < threads; ++t)
    {
        const MaskWorker& m = s.mask_workers[size_t(t)];
        for (size_t gi = 0; gi < G; ++gi) s.group_area[gi] += m.area[gi];
        for (size_t k = 0; k < G * P; ++k) s.group_inter[k] += m.inter[k];
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
    for (const auto& [from, to] : s.fragment_merges) into[from] = to;
    const auto root = [&](uint32_t z) {
        for (auto it = into.find(z); it != into.end(); it = into.find(z)) z = it->second;
        return z;
    };
    renameInstances(root);
    st.merged_fragments += into.size();
    // Evidence about a merged id now concerns its root: start those pairs afresh.
    for (auto it = s.pair_evidence.begin(); it != s.pair_evidence.end();)
        if (into.count(uint32_t(it->first >> 32)) || into.count(uint32_t(it->first)))
            it = s.pair_evidence.erase(it);
        else
            ++it;
    s.fragment_merges.clear();
}

void PanopticMap::classifyMapInstances()
{
    Scratch& s = *scratch_;
    const size_t G = s.groups.size();
    // Class of each map instance: the thing class with the most semantic mass over
    // its voxels in view (the propagation rule, on what the frame sees).
    const ClassSet& classes = options_.classes;
    s.class_mass.resize(classes.size());
    s.group_class.assign(G, 0);
    for (size_t gi = 0; gi < G; ++gi)
    {
        std::fill(s.class_mass.begin(), s.class_mass.end(), 0.f);
        for (size_t c = s.groups[gi].first; c < s.groups[gi].second; ++c)
        {
            const Voxel& v = store_[s.candidates[c].second];
            addThingMass(*labelsOf(v), classes, s.class_mass.data(), spillOf(v));
        }
        const auto best = std::max_element(s.class_mass.begin(), s.class_mass.end());
        if (*best > 0) s.group_class[gi] = uint16_t(best - s.class_mass.begin());
    }
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
    for (size_t gi = 0; gi < G; ++gi)
    {
        const uint16_t gc = s.group_class[gi];
        if (gc == 0 || s.group_area[gi] == 0) continue;
        const uint32_t z = s.candidates[s.groups[gi].first].first;
        for (size_t p = 0; p < P; ++p)
        {
            if (g.cls[p] == 0 || g.cls[p] == gc || s.assignment[p] == int32_t(gi)) continue;
            if (double(s.group_inter[gi * P + p]) < options_.split_coverage * double(s.group_area[gi])) continue;
            // p swallowed most of a map instance of another class: its pixels there
            // keep that instance, except on voxels that are of p's class themselves
            // (an early merge in the map that p now resolves).
            ++st.split_predictions;
            s.split_pixels = true;
            for (size_t c = s.groups[gi].first; c < s.groups[gi].second; ++c)
                if (const Voxel& v = store_[s.candidates[c].second]; ownThingClass(*labelsOf(v), classes, spillOf(v)) != g.cls[p])
                    forEachFootprintPixel(s.footprints[c], s.footprints[c].r0, s.footprints[c].r1 + 1, f,
                                          [&](size_t i, int32_t q) {
                                              if (q != int32_t(p)) return;
                                              s.split_stamp[i] = stamp;
                                              s.split_id[i] = z;
                                          });
        }
    }
}

MaskFootprint PanopticMap::maskFootprint(uint32_t voxel, const Pose& T_cam_world, const CameraIntrinsics& K) const
{
    const Voxel& v = store_[voxel];
    if (options_.use_ndt && hasGaussian(v))
        return gaussianFootprint(gaussianOf(v), T_cam_world, K, options_.vtou_mahalanobis_sq);
    // Cube ablation (or too few samples): the projected voxel's bounding box.
    return cubeFootprint(grid_.minCorner(store_.key(voxel)), options_.voxel_size, T_cam_world, K);
}

template <class Visit>
void PanopticMap::forEachFootprintPixel(const MaskFootprint& fp, int row_begin, int row_end, const FramePixels& f,
                                        Visit&& visit)
{
    Scratch& s = *scratch_;
    const int W = f.depth.width, H = f.depth.height;
    const double tol = options_.vtou_depth_tolerance * options_.voxel_size;
    const double k2 = options_.vtou_mahalanobis_sq;
    const int32_t* predicted = s.pixel_predicted.data();
    const float* depth = f.depth.data.data();
    for (int r = row_begin; r < row_end; ++r)
    {
        const int32_t* to_frame = s.predicted_bands[size_t(s.bandOfRow(r, H))].remap.data();
        int a, b;
        if (!footprintRow(fp, r, k2, a, b)) continue;
        const size_t row = size_t(r) * W;
        for (int c = a; c <= b; ++c)
        {
            const size_t i = row + c;
            const int32_t p = predicted[i];
            if (p == kUnmappedPixel || !agreesInDepth(fp, depth[i], tol)) continue;
            visit(i, p >= 0 ? to_frame[p] : p);
        }
    }
}

}  // namespace pndt
