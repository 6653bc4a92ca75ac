// Spatial relations (spatial_relations.h).
#include <pndt/nav/spatial_relations.h>

#include <algorithm>
#include <limits>

namespace pndt::nav
{
bool isOnTopOf(const MapObject& upper, const MapObject& lower, const RelationOptions& o)
{
    if (upper.id == lower.id) return false;
    return std::abs(upper.z_min - lower.z_max) <= o.on_top_z_tolerance && upper.z_max > lower.z_max &&
           lower.footprint.contains(upper.centroid.head<2>());
}

bool isNextTo(const MapObject& a, const MapObject& b, const RelationOptions& o)
{
    if (a.id == b.id || isOnTopOf(a, b, o) || isOnTopOf(b, a, o)) return false;
    const bool heights_overlap = a.z_min <= b.z_max && b.z_min <= a.z_max;
    return heights_overlap && footprintDistance(a.footprint, b.footprint) <= o.next_to_distance;
}

bool areFragmentsOfOne(const MapObject& a, const MapObject& b)
{
    if (a.id == b.id || a.class_id != b.class_id) return false;
    // Either way round: a chair's back has more voxels than its seat, yet the
    // smaller footprint.
    return a.footprint.contains(b.footprint.center) || b.footprint.contains(a.footprint.center);
}

namespace
{
/// Objects of one class grouped into things (transitive fragments), largest piece first.
std::vector<std::vector<const MapObject*>> thingsOfClass(const std::vector<MapObject>& objects, int class_id)
{
    std::vector<const MapObject*> of;
    for (const MapObject& m : objects)
        if (m.class_id == class_id) of.push_back(&m);
    std::vector<size_t> parent(of.size());
    for (size_t i = 0; i < of.size(); ++i) parent[i] = i;
    auto root = [&](size_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    for (size_t i = 0; i < of.size(); ++i)
        for (size_t j = i + 1; j < of.size(); ++j)
            if (areFragmentsOfOne(*of[i], *of[j])) parent[root(i)] = root(j);
    std::map<size_t, std::vector<const MapObject*>> groups;
    for (size_t i = 0; i < of.size(); ++i) groups[root(i)].push_back(of[i]);
    std::vector<std::vector<const MapObject*>> out;
    for (auto& [r, g] : groups)
    {
        std::stable_sort(g.begin(), g.end(), [](const MapObject* x, const MapObject* y) { return x->voxel_count > y->voxel_count; });
        out.push_back(g);
    }
    return out;
}
}  // namespace

std::map<uint32_t, std::vector<uint32_t>> objectsAround(const std::vector<MapObject>& objects, int center_class,
                                                        int around_class, const RelationOptions& o)
{
    std::map<uint32_t, std::vector<uint32_t>> out;
    std::vector<const MapObject*> centres;
    for (const MapObject& m : objects)
        if (m.class_id == center_class)
        {
            centres.push_back(&m);
            out[m.id];
        }
    if (around_class == center_class) return out;
    for (const auto& thing : thingsOfClass(objects, around_class))
    {
        const MapObject* best = nullptr;
        double best_d = std::numeric_limits<double>::infinity();
        for (const MapObject* c : centres)
            for (const MapObject* m : thing)
            {
                if (isOnTopOf(*m, *c, o)) continue;  // a lamp on a table is not around it
                const double d = footprintDistance(m->footprint, c->footprint);
                // Ties (both overlap): the nearer centroid.
                const double key = d + 1e-6 * (m->centroid.head<2>() - c->centroid.head<2>()).norm();
                if (d <= o.around_distance && key < best_d)
                {
                    best_d = key;
                    best = c;
                }
            }
        if (best) out[best->id].push_back(thing.front()->id);
    }
    for (auto& [id, v] : out) std::sort(v.begin(), v.end());
    return out;
}

std::vector<std::pair<const MapObject*, double>> nearestTo(const std::vector<MapObject>& objects, int class_id,
                                                           const Eigen::Vector2d& p)
{
    std::vector<std::pair<const MapObject*, double>> out;
    for (const MapObject& m : objects)
        if (class_id < 0 || m.class_id == class_id) out.emplace_back(&m, m.footprint.distanceTo(p));
    std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    return out;
}

}  // namespace pndt::nav
