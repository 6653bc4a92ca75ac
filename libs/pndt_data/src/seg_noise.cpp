// SegmentationNoiseModel::apply — see seg_noise.h for the model.
#include "pndt/data/seg_noise.h"

#include <pndt/sim/nyu40_extra.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <climits>
#include <numeric>

#include "pndt/data/confusion.h"
#include "pndt/data/random.h"
#include "pndt/data/segment_analysis.h"
#include "seg_internal.h"

namespace pndt::data
{
namespace n40 = pndt::sim::nyu40;
using detail::Decision;

namespace
{
/// A hallucinated object on a world-anchored patch of stuff.
struct PhantomCell
{
    bool active = false;
    Eigen::Vector3f center;
    float radius2 = 0;
    uint16_t cls = 0;
    double score_u = 0.5;
};

constexpr double kPhantomCell = 1.2;  // metres

/// Scores are multiples of 1/1024 (exact in float next to any id < 16384; keeps the
/// packed id+score images compressible).
double quantiseScore(double s) { return std::min(std::floor(s * 1024.0 + 0.5), 1022.0) / 1024.0; }
}  // namespace

SegmentationNoiseModel::SegmentationNoiseModel(const std::vector<sim::SceneObject>& objects,
                                               const SegNoiseOptions& options)
    : o_(options)
{
    for (const auto& ob : objects) objects_[ob.instance] = ob;
}

SegNoiseFrame SegmentationNoiseModel::apply(const Image<uint16_t>& gt_sem, const Image<uint32_t>& gt_ins,
                                            const Image<float>& depth, const FrameGeometry& geo,
                                            uint64_t frame_index) const
{
    const int W = gt_sem.width, H = gt_sem.height;
    const FrameSegments fs = analyseSegments(gt_sem, gt_ins, depth, geo);
    const int nseg = static_cast<int>(fs.segments.size());
    const double s = std::max(0.0, o_.strength);
    const double spread = std::min(1.0, s);
    const double scale = W / 640.0;
    const uint64_t frame_key = hashKeys({o_.seed, frame_index, 0xF4A3Eull});
    const double f = std::clamp(o_.flicker, 0.0, 1.0), keep = std::sqrt(1 - f * f);

    // --- 1. one decision per ground-truth segment; merge groups ------------------------
    std::vector<int> root;
    std::vector<Decision> dec = detail::decideSegments(fs, {o_, objects_, geo, W, H, frame_key}, root);

    // --- 2. boundary bleeding ----------------------------------------------------------
    const std::vector<int32_t> assigned = detail::bleed(fs, dec, hashKeys({frame_key, 0x1A6ull}), 6.0 * scale);

    // --- 3. split sides (cancel splits that cut off < 20 %) ---------------------------
    std::vector<uint8_t> side(assigned.size(), 0);
    {
        std::vector<int> side_b(static_cast<size_t>(nseg), 0);
        for (size_t i = 0; i < assigned.size(); ++i)
        {
            const int a = assigned[i];
            if (a < 0 || !dec[a].split || !(depth.data[i] > 0)) continue;
            const Eigen::Vector3d p = geo.world[i].cast<double>();
            side[i] = (p - dec[a].split_origin).dot(dec[a].split_normal) > 0 ? 1 : 0;
            if (fs.index[i] == a) side_b[a] += side[i];
        }
        for (int k = 0; k < nseg; ++k)
            if (dec[k].split)
            {
                const double frac = double(side_b[k]) / std::max(1, fs.segments[k].depth_n);
                if (frac < 0.1 || frac > 0.9) dec[k].split = false;
            }
    }

    // --- 4. predicted class and slot (future instance) of every pixel -----------------
    // Slots: 2k = main part of group root k, 2k+1 = split part of k, 2n+j = phantom j.
    // Class of a group: the decided class of its largest member (the merge rule).
    std::vector<uint16_t> group_cls(static_cast<size_t>(nseg), 0);
    {
        std::vector<int> group_best(static_cast<size_t>(nseg), -1);
        for (int k = 0; k < nseg; ++k)
        {
            if (!fs.segments[k].thing) continue;
            const int r = root[k];
            if (group_best[r] < 0 || fs.segments[k].area > group_best[r])
            {
                group_best[r] = fs.segments[k].area;
                group_cls[r] = dec[k].cls;
            }
        }
    }
    SegNoiseFrame out;
    out.semantic.resize(W, H, 0);
    out.instance.resize(W, H, 0);
    out.semantic_score.resize(W, H, 0.f);
    out.panoptic_score.resize(W, H, 0.f);
    std::vector<int64_t> slot(assigned.size(), -1);
    std::vector<PhantomCell> phantoms;
    std::unordered_map<uint64_t, int> phantom_of_cell;
    // World-anchored hallucination patches on stuff, evaluated once per (cell, class).
    auto cellPhantom = [&](int64_t cx, int64_t cy, int64_t cz, uint16_t sem)
    {
        const uint64_t cell_key = hashKeys({uint64_t(cx), uint64_t(cy), uint64_t(cz), sem});
        auto [it, inserted] = phantom_of_cell.try_emplace(cell_key, -1);
        if (!inserted) return it->second;
        const uint64_t h = hashKeys({o_.seed, cell_key, 0xFA27ull});
        PhantomCell pc;
        const Eigen::Vector3d lo(cx * kPhantomCell, cy * kPhantomCell, cz * kPhantomCell);
        const double radius = 0.15 + 0.2 * toUniform(mix64(h + 1));
        Eigen::Vector3d c;
        for (int ax = 0; ax < 3; ++ax)
            c[ax] = lo[ax] + radius + (kPhantomCell - 2 * radius) * toUniform(mix64(h + 2 + ax));
        pc.center = c.cast<float>();
        pc.radius2 = static_cast<float>(radius * radius);
        pc.cls = 0;
        const auto& list = phantomsOn(sem);
        if (!list.empty())
        {
            double u = toUniform(mix64(h + 9)), acc = 0;
            pc.cls = list.back().semantic;
            for (const auto& cc : list)
                if (u < (acc += cc.weight))
                {
                    pc.cls = cc.semantic;
                    break;
                }
            const ViewLatent lat(h);
            const double z = keep * lat(viewDescriptor(c, geo.eye, o_.angular_scale, o_.distance_scale)) +
                             f * toNormal(hashKeys({frame_key, cell_key}));
            const double dist = (c - geo.eye).norm();
            const double hz =
                1.0 - std::exp(-s * o_.phantom_rate * std::exp(0.8 * std::clamp((dist - 1.5) / 2.5, 0.0, 2.0)));
            pc.active = normalCdf(z) < hz;
            pc.score_u = toUniform(mix64(h + 17));
        }
        if (pc.active)
        {
            it->second = static_cast<int>(phantoms.size());
            phantoms.push_back(pc);
        }
        return it->second;
    };
    int64_t last_cell[4] = {INT64_MIN, 0, 0, 0};
    int last_phantom = -1;
    for (size_t i = 0; i < assigned.size(); ++i)
    {
        const int a = assigned[i];
        if (a < 0) continue;
        const SegmentInfo& sg = fs.segments[a];
        if (sg.thing)
        {
            const Decision& d = dec[a];
            if (d.drop && d.absorb < 0)
            {
                out.semantic.data[i] = d.fill;
                continue;
            }
            if (d.drop)
            {
                const int r = root[d.absorb];
                out.semantic.data[i] = group_cls[r];
                if (n40::isThing(group_cls[r])) slot[i] = 2 * int64_t(r);
                continue;
            }
            const int r = root[a];
            const bool part = d.split && side[i];
            const uint16_t cls = part ? d.part_cls : group_cls[r];
            out.semantic.data[i] = cls;
            if (n40::isThing(cls)) slot[i] = part ? 2 * int64_t(a) + 1 : 2 * int64_t(r);
            continue;
        }
        out.semantic.data[i] = sg.semantic;
        if (!(s > 0) || !(depth.data[i] > 0)) continue;
        const Eigen::Vector3f& p = geo.world[i];
        const int64_t cx = static_cast<int64_t>(std::floor(p.x() / kPhantomCell));
        const int64_t cy = static_cast<int64_t>(std::floor(p.y() / kPhantomCell));
        const int64_t cz = static_cast<int64_t>(std::floor(p.z() / kPhantomCell));
        if (cx != last_cell[0] || cy != last_cell[1] || cz != last_cell[2] || sg.semantic != last_cell[3])
        {
            last_cell[0] = cx, last_cell[1] = cy, last_cell[2] = cz, last_cell[3] = sg.semantic;
            last_phantom = cellPhantom(cx, cy, cz, sg.semantic);
        }
        const int ph = last_phantom;
        if (ph >= 0 && (p - phantoms[ph].center).squaredNorm() < phantoms[ph].radius2)
        {
            out.semantic.data[i] = phantoms[ph].cls;
            if (n40::isThing(phantoms[ph].cls)) slot[i] = 2 * int64_t(nseg) + ph;
        }
    }

    // --- 5. instance ids: a fresh permutation every frame -----------------------------
    std::vector<int64_t> used;
    {
        std::vector<int> seen(static_cast<size_t>(2 * nseg) + phantoms.size(), 0);
        for (int64_t sl : slot)
            if (sl >= 0) seen[sl] = 1;
        for (size_t k = 0; k < seen.size(); ++k)
            if (seen[k]) used.push_back(static_cast<int64_t>(k));
    }
    std::vector<uint32_t> id_of(static_cast<size_t>(2 * nseg + phantoms.size()), 0);
    {
        std::vector<uint32_t> ids(used.size());
        std::iota(ids.begin(), ids.end(), 1u);
        if (o_.permute_ids)
        {
            Rng r(hashKeys({frame_key, 0x1D5ull}));
            for (size_t k = ids.size(); k > 1; --k) std::swap(ids[k - 1], ids[r.below(k)]);
        }
        for (size_t k = 0; k < used.size(); ++k) id_of[used[k]] = ids[k];
    }
    for (size_t i = 0; i < slot.size(); ++i)
        if (slot[i] >= 0) out.instance.data[i] = id_of[slot[i]];
    out.phantoms = 0;
    for (int64_t sl : used) out.phantoms += sl >= 2 * nseg ? 1 : 0;

    // --- 6. scores -----------------------------------------------------------------------
    // S^L says whether a pixel's class is right; the instance score whether the slot's
    // grouping is right too. A network's semantic confidence does not drop because its
    // instance post-processing split an object or merged it with a neighbour.
    auto slotClassOk = [&](int64_t sl, double& u, double& diff)
    {
        if (sl >= 2 * nseg)
        {
            u = phantoms[sl - 2 * nseg].score_u;
            diff = 1.0;
            return false;
        }
        const int k = static_cast<int>(sl / 2);
        u = dec[k].score_u;
        diff = dec[k].difficulty;
        return !dec[k].confuse && group_cls[k] == fs.segments[k].semantic;
    };
    std::vector<uint8_t> in_group(static_cast<size_t>(nseg), 0);
    for (int k = 0; k < nseg; ++k)
        if (root[k] != k) in_group[k] = in_group[root[k]] = 1;
    const size_t nslots = id_of.size();
    std::vector<double> slot_base(nslots, 0.0), slot_wrong(nslots, 0.0), slot_inst(nslots, 0.0);
    for (int64_t sl : used)
    {
        double u, diff;
        const bool class_ok = slotClassOk(sl, u, diff);
        const bool grouping_ok =
            class_ok && !(sl & 1) && !dec[sl / 2].split && !in_group[sl / 2];  // phantoms: class_ok false
        const double d01 = diff / (1.0 + diff);
        slot_wrong[sl] = 0.98 - spread * (0.45 + 0.2 * u);
        slot_base[sl] = sl < 2 * nseg ? 0.98 - spread * (0.2 * d01 + 0.12 * u) : slot_wrong[sl];
        slot_inst[sl] = grouping_ok ? 0.96 - spread * (0.25 * d01 + 0.1 * u) : 0.96 - spread * (0.45 + 0.2 * u);
    }
    const std::vector<float> bdist = [&]
    {
        std::vector<int64_t> lab(slot.size());
        for (size_t i = 0; i < slot.size(); ++i) lab[i] = slot[i] >= 0 ? (1 << 20) + slot[i] : out.semantic.data[i];
        return detail::boundaryDistance(lab, W, H, 64.f);
    }();
    std::vector<double> sum_l(nslots, 0.0);
    std::vector<int> cnt_l(nslots, 0);
    for (size_t i = 0; i < slot.size(); ++i)
    {
        if (out.semantic.data[i] == 0 && fs.index[i] < 0) continue;
        if (!(s > 0))
        {
            out.semantic_score.data[i] = out.panoptic_score.data[i] = 0.999f;
            continue;
        }
        double base;
        if (slot[i] >= 0)
        {
            // Per pixel: a merged group carries one class, right for some members only.
            const int a = fs.index[i];
            const bool pixel_wrong = a < 0 || out.semantic.data[i] != fs.segments[a].semantic;
            base = pixel_wrong ? slot_wrong[slot[i]] : slot_base[slot[i]];
        }
        else
        {
            const int a = assigned[i];
            const bool wrong = a < 0 || out.semantic.data[i] != fs.segments[a].semantic;
            const double u = a >= 0 ? dec[a].score_u : 0.5;
            base = wrong ? 0.98 - spread * (0.45 + 0.2 * u) : 0.98 - spread * (0.05 + 0.12 * u);
        }
        const double edge = std::max(0.0, 1.0 - bdist[i] / (4.0 * scale));
        double sl =
            base * (1.0 - spread * 0.45 * edge) + spread * 0.02 * toTriangular(hashKeys({frame_key, i, 0x5Cull}));
        sl = quantiseScore(std::clamp(sl, 0.02, 0.999));
        out.semantic_score.data[i] = static_cast<float>(sl);
        if (slot[i] >= 0)
        {
            sum_l[slot[i]] += sl;
            ++cnt_l[slot[i]];
        }
        else
            out.panoptic_score.data[i] = static_cast<float>(sl);
    }
    if (s > 0)
        for (size_t i = 0; i < slot.size(); ++i)
            if (slot[i] >= 0)
            {
                const int64_t sl = slot[i];
                out.panoptic_score.data[i] = static_cast<float>(
                    quantiseScore(std::clamp(slot_inst[sl] * sum_l[sl] / std::max(1, cnt_l[sl]), 0.0, 0.999)));
            }

    // --- 7. what happened to each visible object ----------------------------------------
    for (int k = 0; k < nseg; ++k)
    {
        const SegmentInfo& sg = fs.segments[k];
        if (!sg.thing) continue;
        InstanceOutcome oc;
        oc.gt_instance = sg.instance;
        oc.gt_semantic = sg.semantic;
        oc.area = sg.area;
        oc.difficulty = dec[k].difficulty;
        oc.dropped = dec[k].drop;
        oc.confused = !dec[k].drop && dec[k].cls != sg.semantic;
        oc.split = !dec[k].drop && dec[k].split;
        oc.merged = !dec[k].drop && in_group[k];
        const int r = root[k];
        if (dec[k].drop && dec[k].absorb >= 0)
        {
            const int ra = root[dec[k].absorb];
            oc.pred_semantic = group_cls[ra];
            oc.pred_instance = n40::isThing(group_cls[ra]) ? id_of[2 * ra] : 0;
        }
        else
        {
            oc.pred_semantic = dec[k].drop ? dec[k].fill : group_cls[r];
            oc.pred_instance = dec[k].drop || !n40::isThing(group_cls[r]) ? 0 : id_of[2 * r];
        }
        out.outcomes.push_back(oc);
    }
    std::sort(out.outcomes.begin(), out.outcomes.end(),
              [](const InstanceOutcome& a, const InstanceOutcome& b) { return a.gt_instance < b.gt_instance; });
    return out;
}

}  // namespace pndt::data
