// Paper step 7: panoptic label propagation, computed lazily on query.
#include <pndt/instance_rules.h>
#include <tsl/robin_map.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "map_scratch.h"

namespace pndt
{
void PanopticMap::classifyInstances() const
{
    // Eq. 9: the summed thing histogram of every instance over its voxels, in
    // voxel order: the voxels that take it (pthing, default) or every voxel
    // whose top h^Z entry it is (the paper's sum; option instance_class_voxels).
    Propagation& pr = *prop_;
    const size_t n = store_.size();
    const size_t C = options_.classes.size();
    const bool every_top = options_.instance_class_voxels == InstanceClassVoxels::TopInstance;
    tsl::robin_map<uint32_t, uint32_t> row_of;
    std::vector<double> class_mass;  // rows of C
    for (size_t i = 0; i < n; ++i)
    {
        uint32_t z = propagatedInstance(uint32_t(i));
        if (z == 0 && every_top) z = strongestInstance(store_[uint32_t(i)]);
        if (z == 0) continue;
        const LabelRecord& rec = *labelsOf(store_[uint32_t(i)]);
        const auto [it, inserted] = row_of.try_emplace(z, uint32_t(row_of.size()));
        if (inserted) class_mass.resize(class_mass.size() + C, 0.0);
        double* row = &class_mass[size_t(it->second) * C];
        addThingMass(rec, options_.classes, row, spillOf(store_[uint32_t(i)]));
    }
    pr.instance_class.clear();
    pr.instance_class.reserve(row_of.size());
    for (const auto& [z, row_index] : row_of)
    {
        const double* row = &class_mass[size_t(row_index) * C];
        pr.instance_class.emplace(z, uint16_t(std::max_element(row, row + C) - row));
    }
}

void PanopticMap::ensurePropagated() const
{
    if (propagated_valid_) return;
    Propagation& pr = *prop_;
    const size_t n = store_.size();
    pr.instances.clear();
    pr.instance_of_voxel.clear();
    pr.absorbed_into.clear();
    pr.filled.clear();

    // Pass 1: instance classes from the top instance of every voxel.
    classifyInstances();

    // Pass 1b: a voxel whose own class is not its instance's (the rug that an
    // early merged prediction tied to the chair on it) moves to its strongest
    // instance of its own class; then the classes are summed again.
    if (options_.class_consistent_instances)
    {
        for (size_t i = 0; i < n; ++i)
        {
            const Voxel& v = store_[uint32_t(i)];
            const uint32_t z = topInstance(v);
            if (z == 0) continue;
            const LabelRecord& rec = *labelsOf(v);
            const uint16_t own = ownThingClass(rec, options_.classes, spillOf(v));
            if (own == 0 || own == pr.instance_class.at(z)) continue;
            const auto& hist = instance_records_[rec.instances].hist;
            for (int j = 1, n = hist.size(); j < n; ++j)  // by weight, strongest first
            {
                const auto it = pr.instance_class.find(hist.ids[j]);
                if (it != pr.instance_class.end() && it->second == own &&
                    isInTopZ(hist, hist.ids[j], options_.theta_b))
                {
                    pr.instance_of_voxel.emplace(uint32_t(i), hist.ids[j]);
                    break;
                }
            }
        }
        if (!pr.instance_of_voxel.empty()) classifyInstances();
    }

    // Every voxel's instance, looked up once for the passes below.
    std::vector<uint32_t> instance(n);
    for (size_t i = 0; i < n; ++i) instance[i] = propagatedInstance(uint32_t(i));

    // Pass 1c: finalisation beyond the paper (map_options.h): fragments join
    // their object, then unlabelled surface takes its labelled neighbours' label.
    if (options_.fragment_absorb_ratio > 0) absorbFragments(instance);
    if (options_.label_fill_distance > 0) fillUnlabelled(instance);

    // Pass 2: the instance summaries (centroid, extent, count, confidence).
    tsl::robin_map<uint32_t, uint32_t> summary_of;
    std::vector<double> own_weight, all_weight;  // per summary: h^Z weight of it / of all ids
    for (size_t i = 0; i < n; ++i)
    {
        const uint32_t z = instance[i];
        if (z == 0) continue;
        const Eigen::Vector3d p = pointOf(uint32_t(i));
        const auto [it, inserted] = summary_of.try_emplace(z, uint32_t(pr.instances.size()));
        if (inserted)
        {
            MapInstance mi;
            mi.id = z;
            mi.semantic = pr.instance_class.at(z);
            mi.bbox_min = mi.bbox_max = p;
            pr.instances.push_back(mi);
            own_weight.push_back(0);
            all_weight.push_back(0);
        }
        MapInstance& mi = pr.instances[it->second];
        if (const LabelRecord* rec = labelsOf(store_[uint32_t(i)]); rec && rec->instances != kNoRecord)
        {
            const auto& h = instance_records_[rec->instances].hist;
            own_weight[it->second] += h.weightOf(z);
            all_weight[it->second] += h.sum();
        }
        ++mi.voxel_count;
        mi.centroid += p;
        mi.bbox_min = mi.bbox_min.cwiseMin(p);
        mi.bbox_max = mi.bbox_max.cwiseMax(p);
    }
    for (size_t k = 0; k < pr.instances.size(); ++k)
    {
        MapInstance& mi = pr.instances[k];
        mi.centroid /= double(mi.voxel_count);
        mi.weight_share = all_weight[k] > 0 ? float(own_weight[k] / all_weight[k]) : 0.f;
        const auto seen = instance_frames_.find(mi.id);
        mi.frames_seen = seen == instance_frames_.end() ? 0 : seen->second;
        mi.confidence = instanceConfidence(mi.weight_share, mi.frames_seen);
    }
    std::sort(pr.instances.begin(), pr.instances.end(),
              [](const MapInstance& a, const MapInstance& b) { return a.id < b.id; });
    propagated_valid_ = true;
}

uint32_t PanopticMap::propagatedInstance(uint32_t voxel) const
{
    const Propagation& pr = *prop_;
    const auto moved = pr.instance_of_voxel.empty() ? pr.instance_of_voxel.end() : pr.instance_of_voxel.find(voxel);
    uint32_t z = moved != pr.instance_of_voxel.end() ? moved->second : topInstance(store_[voxel]);
    if (z != 0 && !pr.absorbed_into.empty())
    {
        const auto it = pr.absorbed_into.find(z);
        if (it != pr.absorbed_into.end()) z = it->second;
    }
    if (z == 0 && !pr.filled.empty())
    {
        const auto it = pr.filled.find(voxel);
        if (it != pr.filled.end()) z = it->second.instance;
    }
    return z;
}

namespace
{
/// The 13 neighbour offsets after (0,0,0) in lexicographic order: with them
/// every touching pair of voxels is visited once.
constexpr int kForward[13][3] = {{0, 0, 1},  {0, 1, -1}, {0, 1, 0},  {0, 1, 1},  {1, -1, -1},
                                 {1, -1, 0}, {1, -1, 1}, {1, 0, -1}, {1, 0, 0},  {1, 0, 1},
                                 {1, 1, -1}, {1, 1, 0},  {1, 1, 1}};
}  // namespace

void PanopticMap::absorbFragments(std::vector<uint32_t>& instance) const
{
    Propagation& pr = *prop_;
    const size_t n = store_.size();
    tsl::robin_map<uint32_t, uint32_t> size_of;
    for (size_t i = 0; i < n; ++i)
        if (const uint32_t z = instance[i]) ++size_of[z];
    if (size_of.size() < 2) return;

    // Touching voxel pairs of two instances of one class.
    tsl::robin_map<uint64_t, uint32_t> contacts;
    for (size_t i = 0; i < n; ++i)
    {
        const uint32_t a = instance[i];
        if (a == 0) continue;
        const uint16_t class_a = pr.instance_class.at(a);
        const VoxelKey k = store_.key(uint32_t(i));
        for (const auto& d : kForward)
        {
            const uint32_t j = store_.find({k.x + d[0], k.y + d[1], k.z + d[2]});
            if (j == kNoRecord) continue;
            const uint32_t b = instance[j];
            if (b == 0 || b == a || pr.instance_class.at(b) != class_a) continue;
            ++contacts[(uint64_t(std::min(a, b)) << 32) | std::max(a, b)];
        }
    }
    // A fragment joins the partner it is small against that it touches most
    // (ties: the larger partner, then the older id). Partners are strictly
    // larger, so following the joins ends.
    struct Pick
    {
        uint32_t into = 0, contacts = 0, size = 0;
    };
    tsl::robin_map<uint32_t, Pick> pick;
    for (const auto& [pair, c] : contacts)
    {
        const uint32_t ids[2] = {uint32_t(pair >> 32), uint32_t(pair)};
        for (int s = 0; s < 2; ++s)
        {
            const uint32_t small = ids[s], large = ids[1 - s];
            const uint32_t ns = size_of.at(small), nl = size_of.at(large);
            if (double(ns) > options_.fragment_absorb_ratio * double(nl)) continue;
            Pick& p = pick[small];
            if (std::tie(c, nl) > std::tie(p.contacts, p.size) ||
                (c == p.contacts && nl == p.size && large < p.into))
                p = {large, c, nl};
        }
    }
    for (const auto& [small, p] : pick)
    {
        uint32_t root = p.into;
        for (auto it = pick.find(root); it != pick.end(); it = pick.find(root)) root = it->second.into;
        pr.absorbed_into.emplace(small, root);
    }
    if (pr.absorbed_into.empty()) return;
    for (uint32_t& z : instance)
        if (z != 0)
            if (const auto it = pr.absorbed_into.find(z); it != pr.absorbed_into.end()) z = it->second;
}

void PanopticMap::fillUnlabelled(std::vector<uint32_t>& instance) const
{
    if (labels_.empty()) return;  // a geometry-only map has nothing to pass on
    Propagation& pr = *prop_;
    const int steps = int(std::ceil(options_.label_fill_distance / options_.voxel_size - 1e-9));
    std::vector<uint32_t> todo;
    for (size_t i = 0; i < store_.size(); ++i)
    {
        const Voxel& v = store_[uint32_t(i)];
        const LabelRecord* rec = labelsOf(v);
        if (isOccupied(v) && (!rec || rec->semantic.empty())) todo.push_back(uint32_t(i));
    }
    // The label a voxel passes on: its own (propagated) one, or one filled in an
    // earlier step; voxels filled in this step pass nothing on yet.
    const auto labelOf = [&](uint32_t j, PanopticLabel& out) {
        const Voxel& v = store_[j];
        if (!isOccupied(v)) return false;
        const LabelRecord* rec = labelsOf(v);
        if (rec && !rec->semantic.empty())
        {
            out = labelledLabel(*rec, instance[j]);
            return true;
        }
        const auto it = pr.filled.find(j);
        if (it == pr.filled.end()) return false;
        out = it->second;
        return true;
    };
    std::vector<std::pair<uint32_t, PanopticLabel>> decided;
    for (int step = 0; step < steps && !todo.empty(); ++step)
    {
        decided.clear();
        size_t kept = 0;
        for (const uint32_t u : todo)
        {
            // The most common label among the 26 neighbours; ties: the smallest
            // <class, instance>, so the result does not depend on visiting order.
            PanopticLabel seen[26];
            int count[26] = {};
            int distinct = 0;
            const VoxelKey k = store_.key(u);
            for (int dx = -1; dx <= 1; ++dx)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dz = -1; dz <= 1; ++dz)
                    {
                        if (dx == 0 && dy == 0 && dz == 0) continue;
                        const uint32_t j = store_.find({k.x + dx, k.y + dy, k.z + dz});
                        PanopticLabel l;
                        if (j == kNoRecord || !labelOf(j, l)) continue;
                        int s = 0;
                        while (s < distinct && !(seen[s] == l)) ++s;
                        if (s == distinct) seen[distinct++] = l;
                        ++count[s];
                    }
            if (distinct == 0)
            {
                todo[kept++] = u;
                continue;
            }
            int best = 0;
            for (int s = 1; s < distinct; ++s)
                if (count[s] > count[best] ||
                    (count[s] == count[best] && std::tie(seen[s].semantic, seen[s].instance) <
                                                    std::tie(seen[best].semantic, seen[best].instance)))
                    best = s;
            decided.emplace_back(u, seen[best]);
        }
        todo.resize(kept);
        if (decided.empty()) break;
        for (const auto& [u, l] : decided)
        {
            pr.filled.emplace(u, l);
            instance[u] = l.instance;
        }
    }
}

uint32_t PanopticMap::strongestInstance(const Voxel& v) const
{
    if (!isOccupied(v)) return 0;
    const LabelRecord* rec = labelsOf(v);
    return rec && rec->instances != kNoRecord ? instance_records_[rec->instances].hist.top() : 0;
}

uint32_t PanopticMap::topInstance(const Voxel& v) const
{
    if (!isOccupied(v)) return 0;
    const LabelRecord* rec = labelsOf(v);
    if (!rec || rec->instances == kNoRecord) return 0;
    const InstanceRecord& z = instance_records_[rec->instances];
    return isPanopticThing(*rec, z, options_.classes, options_.theta_st, options_.theta_o, spillOf(v)) ? z.hist.top()
                                                                                                        : 0;
}

void PanopticMap::finalize() const { ensurePropagated(); }

PanopticLabel PanopticMap::panopticLabel(uint32_t voxel) const
{
    ensurePropagated();
    if (voxel >= store_.size()) return {};
    const Voxel& v = store_[voxel];
    if (!isOccupied(v)) return {};
    const LabelRecord* rec = labelsOf(v);
    if (!rec || rec->semantic.empty())
    {
        // No semantic evidence: void, or what label_fill_distance gave it.
        const auto it = prop_->filled.find(voxel);
        return it == prop_->filled.end() ? PanopticLabel{} : it->second;
    }
    return labelledLabel(*rec, propagatedInstance(voxel));
}

PanopticLabel PanopticMap::labelledLabel(const LabelRecord& rec, uint32_t instance) const
{
    // pthing voxels take <the instance's class, the instance>; all others <argmax h^L, 0>.
    if (instance == 0) return {semanticArgmax(rec), 0};
    return {prop_->instance_class.at(instance), instance};
}

uint16_t PanopticMap::semanticLabel(uint32_t voxel) const
{
    if (voxel >= store_.size()) return 0;
    const LabelRecord* r = labelsOf(store_[voxel]);
    return r ? semanticArgmax(*r) : 0;
}

std::vector<MapInstance> PanopticMap::instances() const
{
    ensurePropagated();
    return prop_->instances;
}

}  // namespace pndt
