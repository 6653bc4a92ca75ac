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
    for (const MapObject& m : objects)
    {
        if (m.class_id != around_class || m.class_id == center_class) continue;
        const MapObject* best = nullptr;
        double best_d = std::numeric_limits<double>::infinity();
        for (const MapObject* c : centres)
        {
            if (isOnTopOf(m, *c, o)) continue;  // a lamp on a table is not around it
            const double d = footprintDistance(m.footprint, c->footprint);
            // Ties (both overlap): the nearer centroid.
            const double key = d + 1e-6 * (m.centroid.head<2>() - c->centroid.head<2>()).norm();
            if (d <= o.around_distance && key < best_d)
            {
                best_d = key;
                best = c;
            }
        }
        if (best) out[best->id].push_back(m.id);
    }
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
