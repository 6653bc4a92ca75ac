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
/// One instance's occupied voxels and its label evidence.
struct Accumulator
{
    std::vector<VoxelKey> keys;
    std::vector<Eigen::Vector3d> points;
    double class_mass = 0, semantic_mass = 0, id_mass = 0, instance_mass = 0;
    uint64_t updates = 0;
};

/// 26-connected groups of voxels (indices into `keys`), largest first.
std::vector<std::vector<size_t>> connectedPieces(const std::vector<VoxelKey>& keys)
{
    std::unordered_map<uint64_t, size_t> index;
    for (size_t i = 0; i < keys.size(); ++i) index[keys[i].packed()] = i;
    std::vector<bool> seen(keys.size(), false);
    std::vector<std::vector<size_t>> pieces;
    std::vector<size_t> stack;
    for (size_t s = 0; s < keys.size(); ++s)
    {
        if (seen[s]) continue;
        std::vector<size_t> piece;
        stack.assign(1, s);
        seen[s] = true;
        while (!stack.empty())
        {
            const size_t i = stack.back();
            stack.pop_back();
            piece.push_back(i);
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                    {
                        const auto it = index.find(VoxelKey{keys[i].x + dx, keys[i].y + dy, keys[i].z + dz}.packed());
                        if (it == index.end() || seen[it->second]) continue;
                        seen[it->second] = true;
                        stack.push_back(it->second);
                    }
        }
        pieces.push_back(std::move(piece));
    }
    std::stable_sort(pieces.begin(), pieces.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
    return pieces;
}

/// Fills where the object is from its voxels: all of `body` for centroid, box and
/// count, only `core` (its largest piece) for footprint and heights.
void placeObject(MapObject& o, const Accumulator& a, const std::vector<size_t>& body, const std::vector<size_t>& core,
                 double voxel_size)
{
    o.voxel_count = uint32_t(body.size());
    o.centroid.setZero();
    o.bbox_min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    o.bbox_max = -o.bbox_min;
    for (size_t k : body)
    {
        o.centroid += a.points[k];
        o.bbox_min = o.bbox_min.cwiseMin(a.points[k]);
        o.bbox_max = o.bbox_max.cwiseMax(a.points[k]);
    }
    o.centroid /= double(body.size());
    std::vector<Eigen::Vector2d> xy;
    o.z_min = std::numeric_limits<double>::infinity();
    o.z_max = -o.z_min;
    for (size_t k : core)
    {
        xy.push_back(a.points[k].head<2>());
        o.z_min = std::min(o.z_min, a.points[k].z());
        o.z_max = std::max(o.z_max, a.points[k].z());
    }
    o.footprint = minAreaFootprint(xy, 0.5 * voxel_size);
}
}  // namespace

std::vector<MapObject> mapObjects(const PanopticMap& map, const std::string& source, uint32_t min_voxels,
                                  const ObjectOptions& options)
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
        MapObject o;
        o.id = o.instance_id = m.id;
        o.class_id = m.semantic;
        o.frames_seen = m.frames_seen;
        o.confidence = m.confidence;
        o.class_name = classes.contains(m.semantic) ? classes.name(m.semantic) : "class " + std::to_string(m.semantic);
        o.source = source;
        const auto it = acc.find(m.id);
        if (it == acc.end() || it->second.points.empty())
        {
            // No occupied voxel carries it any more: what the core summarised.
            o.voxel_count = m.voxel_count;
            o.centroid = m.centroid;
            o.bbox_min = m.bbox_min;
            o.bbox_max = m.bbox_max;
            o.z_min = m.bbox_min.z();
            o.z_max = m.bbox_max.z();
            o.footprint.center = m.centroid.head<2>();
            o.footprint.half_size = 0.5 * (m.bbox_max - m.bbox_min).head<2>() + Eigen::Vector2d(0.5 * vs, 0.5 * vs);
            if (o.voxel_count >= min_voxels) out.push_back(std::move(o));
            continue;
        }
        const Accumulator& a = it->second;
        o.class_confidence = a.semantic_mass > 0 ? a.class_mass / a.semantic_mass : 0;
        o.instance_confidence = a.instance_mass > 0 ? a.id_mass / a.instance_mass : 0;
        o.instance_updates = a.updates;
        // Pieces: the largest is the object; another piece as large as a real object
        // (a table 2 m away that the matching gave the same id) is an object of its
        // own; small ones (stray voxels, detached legs) stay with the object but do
        // not stretch its footprint.
        const auto pieces = connectedPieces(a.keys);
        o.pieces = uint32_t(pieces.size());
        const size_t split_size =
            std::max<size_t>(options.split_min_voxels, size_t(options.split_min_share * double(pieces[0].size())));
        // Only a piece whose footprint does not overlap the largest piece's is another
        // object: a round table's foot under its top (joined by a pole too thin for
        // the voxels) is not.
        auto footprintOf = [&](const std::vector<size_t>& piece) {
            std::vector<Eigen::Vector2d> xy;
            for (size_t k : piece) xy.push_back(a.points[k].head<2>());
            return minAreaFootprint(xy, 0.5 * vs);
        };
        const Footprint main_footprint = footprintOf(pieces[0]);
        std::vector<size_t> body;
        std::vector<const std::vector<size_t>*> separate;
        for (size_t p = 0; p < pieces.size(); ++p)
        {
            if (p > 0 && pieces[p].size() >= split_size &&
                footprintDistance(main_footprint, footprintOf(pieces[p])) > 0)
                separate.push_back(&pieces[p]);
            else
                body.insert(body.end(), pieces[p].begin(), pieces[p].end());
        }
        placeObject(o, a, body, pieces[0], vs);
        for (size_t k = 0; k < separate.size(); ++k)
        {
            MapObject part = o;
            part.id = m.id + uint32_t(k + 1) * kSplitIdStep;
            part.pieces = 1;
            placeObject(part, a, *separate[k], *separate[k], vs);
            if (part.voxel_count >= min_voxels) out.push_back(std::move(part));
        }
        if (o.voxel_count >= min_voxels) out.push_back(std::move(o));
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
