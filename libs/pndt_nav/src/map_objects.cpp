// Objects from the map's instances (map_objects.h).
#include <pndt/nav/map_objects.h>

#include <algorithm>
#include <cctype>
#include <limits>
#include <map>
#include <unordered_map>

namespace pndt::nav
{
namespace
{
struct Accumulator
{
    std::vector<VoxelKey> keys;
    std::vector<Eigen::Vector3d> points;
    double class_mass = 0, semantic_mass = 0, id_mass = 0, instance_mass = 0;
    uint64_t updates = 0;
};
/// Indices of the largest 26-connected group of voxels, and how many groups there are.
std::vector<size_t> largestPiece(const std::vector<VoxelKey>& keys, uint32_t& pieces)
{
    std::unordered_map<uint64_t, size_t> index;
    for (size_t i = 0; i < keys.size(); ++i) index[keys[i].packed()] = i;
    std::vector<int> label(keys.size(), -1);
    std::vector<size_t> best, current, stack;
    pieces = 0;
    for (size_t s = 0; s < keys.size(); ++s)
    {
        if (label[s] >= 0) continue;
        current.clear();
        stack.assign(1, s);
        label[s] = int(pieces);
        while (!stack.empty())
        {
            const size_t i = stack.back();
            stack.pop_back();
            current.push_back(i);
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                    {
                        const auto it = index.find(VoxelKey{keys[i].x + dx, keys[i].y + dy, keys[i].z + dz}.packed());
                        if (it == index.end() || label[it->second] >= 0) continue;
                        label[it->second] = int(pieces);
                        stack.push_back(it->second);
                    }
        }
        ++pieces;
        if (current.size() > best.size()) best = current;
    }
    return best;
}
}  // namespace

std::vector<MapObject> mapObjects(const PanopticMap& map, const std::string& source, uint32_t min_voxels)
{
    const std::vector<MapInstance> instances = map.instances();
    std::map<uint32_t, Accumulator> acc;
    std::map<uint32_t, uint16_t> class_of;
    for (const MapInstance& m : instances) class_of[m.id] = m.semantic;
    const VoxelStore& store = map.voxels();
    for (uint32_t i = 0; i < store.size(); ++i)
    {
        const Voxel& v = store[i];
        if (!map.isOccupied(v)) continue;
        const PanopticLabel l = map.panopticLabel(i);
        if (l.instance == 0) continue;
        Accumulator& a = acc[l.instance];
        a.keys.push_back(store.key(i));
        a.points.push_back(map.pointOf(i));
        if (const LabelRecord* r = map.labelsOf(v))
        {
            a.semantic_mass += r->semantic.sum();
            a.class_mass += r->semantic.weightOf(uint8_t(class_of[l.instance]));
            if (const InstanceRecord* z = map.instancesOf(*r))
            {
                a.instance_mass += z->hist.sum();
                a.id_mass += z->hist.weightOf(l.instance);
                a.updates += z->n_z;
            }
        }
    }
    const ClassSet& classes = map.options().classes;
    const double vs = map.options().voxel_size;
    std::vector<MapObject> out;
    for (const MapInstance& m : instances)
    {
        if (m.voxel_count < min_voxels) continue;
        MapObject o;
        o.id = m.id;
        o.class_id = m.semantic;
        o.class_name = classes.contains(m.semantic) ? classes.name(m.semantic) : "class " + std::to_string(m.semantic);
        o.voxel_count = m.voxel_count;
        o.centroid = m.centroid;
        o.bbox_min = m.bbox_min;
        o.bbox_max = m.bbox_max;
        o.z_min = m.bbox_min.z();
        o.z_max = m.bbox_max.z();
        o.source = source;
        const auto it = acc.find(m.id);
        if (it != acc.end() && !it->second.points.empty())
        {
            const Accumulator& a = it->second;
            // Where the object is: its largest connected piece (a few stray voxels
            // the network gave its id elsewhere would stretch the footprint).
            std::vector<Eigen::Vector2d> xy;
            o.z_min = std::numeric_limits<double>::infinity();
            o.z_max = -o.z_min;
            for (size_t k : largestPiece(a.keys, o.pieces))
            {
                xy.push_back(a.points[k].head<2>());
                o.z_min = std::min(o.z_min, a.points[k].z());
                o.z_max = std::max(o.z_max, a.points[k].z());
            }
            o.footprint = minAreaFootprint(xy, 0.5 * vs);
            o.class_confidence = a.semantic_mass > 0 ? a.class_mass / a.semantic_mass : 0;
            o.instance_confidence = a.instance_mass > 0 ? a.id_mass / a.instance_mass : 0;
            o.instance_updates = a.updates;
        }
        else
        {
            o.footprint.center = m.centroid.head<2>();
            o.footprint.half_size = 0.5 * (m.bbox_max - m.bbox_min).head<2>() + Eigen::Vector2d(0.5 * vs, 0.5 * vs);
        }
        out.push_back(std::move(o));
    }
    std::sort(out.begin(), out.end(), [](const MapObject& a, const MapObject& b) { return a.id < b.id; });
    return out;
}

const MapObject* findObject(const std::vector<MapObject>& objects, uint32_t id)
{
    for (const MapObject& o : objects)
        if (o.id == id) return &o;
    return nullptr;
}

int classIdFromName(const ClassSet& classes, const std::string& raw)
{
    std::string name;
    for (char c : raw) name += char(std::tolower(static_cast<unsigned char>(c)));
    if (!name.empty() && std::all_of(name.begin(), name.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
    {
        const long id = std::stol(name);
        return classes.contains(uint32_t(id)) ? int(id) : -1;
    }
    auto ends = [&](const std::string& s) { return name.size() > s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0; };
    std::vector<std::string> candidates{name};
    if (ends("ies")) candidates.push_back(name.substr(0, name.size() - 3) + "y");
    if (ends("ves")) candidates.push_back(name.substr(0, name.size() - 3) + "f");
    if (ends("es")) candidates.push_back(name.substr(0, name.size() - 2));
    if (ends("s")) candidates.push_back(name.substr(0, name.size() - 1));
    for (const std::string& c : candidates)
        if (const int id = classes.find(c); id >= 0) return id;
    return -1;
}

}  // namespace pndt::nav
