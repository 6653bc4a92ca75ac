// Paper step 7: panoptic label propagation, computed lazily on query.
#include <pndt/instance_rules.h>
#include <tsl/robin_map.h>

#include <algorithm>

#include "map_scratch.h"

namespace pndt
{
void PanopticMap::classifyInstances() const
{
    // The summed thing histogram of every instance over all voxels that take it
    // (pthing), in voxel order.
    Propagation& pr = *prop_;
    const size_t n = store_.size();
    const size_t C = options_.classes.size();
    tsl::robin_map<uint32_t, uint32_t> row_of;
    std::vector<double> class_mass;  // rows of C
    for (size_t i = 0; i < n; ++i)
    {
        const uint32_t z = propagatedInstance(uint32_t(i));
        if (z == 0) continue;
        const LabelRecord& rec = *labelsOf(store_[uint32_t(i)]);
        const auto [it, inserted] = row_of.try_emplace(z, uint32_t(row_of.size()));
        if (inserted) class_mass.resize(class_mass.size() + C, 0.0);
        double* row = &class_mass[size_t(it->second) * C];
        addThingMass(rec, options_.classes, row);
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
            const uint16_t own = ownThingClass(rec, options_.classes);
            if (own == 0 || own == pr.instance_class.at(z)) continue;
            const auto& hist = instance_records_[rec.instances].hist;
            for (int j = 1; j < hist.size; ++j)  // by weight, strongest first
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

    // Pass 2: the instance summaries (centroid, extent, count).
    tsl::robin_map<uint32_t, uint32_t> summary_of;
    for (size_t i = 0; i < n; ++i)
    {
        const uint32_t z = propagatedInstance(uint32_t(i));
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
        }
        MapInstance& mi = pr.instances[it->second];
        ++mi.voxel_count;
        mi.centroid += p;
        mi.bbox_min = mi.bbox_min.cwiseMin(p);
        mi.bbox_max = mi.bbox_max.cwiseMax(p);
    }
    for (MapInstance& mi : pr.instances) mi.centroid /= double(mi.voxel_count);
    std::sort(pr.instances.begin(), pr.instances.end(),
              [](const MapInstance& a, const MapInstance& b) { return a.id < b.id; });
    propagated_valid_ = true;
}

uint32_t PanopticMap::propagatedInstance(uint32_t voxel) const
{
    if (!prop_->instance_of_voxel.empty())
    {
        const auto it = prop_->instance_of_voxel.find(voxel);
        if (it != prop_->instance_of_voxel.end()) return it->second;
    }
    return topInstance(store_[voxel]);
}

uint32_t PanopticMap::topInstance(const Voxel& v) const
{
    if (!isOccupied(v)) return 0;
    const LabelRecord* rec = labelsOf(v);
    if (!rec || rec->instances == kNoRecord || !isPanopticThing(*rec, options_.theta_st, options_.theta_o)) return 0;
    return instance_records_[rec->instances].hist.top();
}

void PanopticMap::finalize() const { ensurePropagated(); }

PanopticLabel PanopticMap::panopticLabel(uint32_t voxel) const
{
    ensurePropagated();
    if (voxel >= store_.size()) return {};
    const Voxel& v = store_[voxel];
    if (!isOccupied(v)) return {};
    const LabelRecord* rec = labelsOf(v);
    if (!rec) return {};
    // pthing voxels take <the instance's class, the instance>; all others <argmax h^L, 0>.
    const uint32_t z = propagatedInstance(voxel);
    if (z == 0) return {rec->semantic.top(), 0};
    return {prop_->instance_class.at(z), z};
}

uint16_t PanopticMap::semanticLabel(uint32_t voxel) const
{
    if (voxel >= store_.size()) return 0;
    const LabelRecord* r = labelsOf(store_[voxel]);
    return r ? r->semantic.top() : 0;
}

std::vector<MapInstance> PanopticMap::instances() const
{
    ensurePropagated();
    return prop_->instances;
}

}  // namespace pndt
