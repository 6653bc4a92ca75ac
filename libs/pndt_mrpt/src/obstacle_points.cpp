// Obstacle points: occupied voxels' NDT means in a height band (obstacle_points.h).
#include <fmt/format.h>
#include <pndt/mrpt/obstacle_points.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace pndt
{
namespace
{
double median(std::vector<double>& v)
{
    const size_t m = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + m, v.end());
    return v[m];
}

bool sameDouble(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }
}  // namespace

bool ObstacleOptions::operator==(const ObstacleOptions& o) const
{
    return min_height == o.min_height && max_height == o.max_height && reference == o.reference &&
           sameDouble(floor_z, o.floor_z) && excluded_classes == o.excluded_classes;
}

double floorHeight(const PanopticMap& map)
{
    const VoxelStore& store = map.voxels();
    const int floor_class = map.options().classes.find("floor");
    std::vector<double> floor_z;
    std::map<int32_t, std::vector<double>> layers;  // voxel z key -> means' z
    for (uint32_t i = 0; i < store.size(); ++i)
    {
        if (!map.isOccupied(store[i])) continue;
        const double z = map.pointOf(i).z();
        if (floor_class > 0 && map.semanticLabel(i) == floor_class) floor_z.push_back(z);
        layers[store.key(i).z].push_back(z);
    }
    constexpr size_t kMinFloorVoxels = 10;
    if (floor_z.size() >= kMinFloorVoxels) return median(floor_z);
    if (layers.empty()) return 0;
    // Geometry only: the floor is the fullest layer in the lower half of the map.
    const int32_t lo = layers.begin()->first, hi = layers.rbegin()->first;
    const int32_t mid = lo + (hi - lo) / 2;
    std::vector<double>* best = nullptr;
    for (auto& [k, zs] : layers)
        if (k <= mid && (!best || zs.size() > best->size())) best = &zs;
    return median(*best);
}

ObstacleSelection resolveObstacleOptions(const PanopticMap& map, const ObstacleOptions& o)
{
    if (!(o.min_height <= o.max_height))
        throw InputError(fmt::format("obstacle band: min_height {} is above max_height {}", o.min_height, o.max_height));
    const ClassSet& classes = map.options().classes;
    ObstacleSelection sel;
    sel.excluded.assign(classes.size(), false);
    for (const std::string& name : o.excluded_classes)
    {
        const int id = classes.find(name);
        // The defaults name NYUv2-40 classes; a map with another class table may lack them.
        if (id < 0 && (name == "floor" || name == "ceiling")) continue;
        if (id < 0)
        {
            std::string known;
            for (const auto& c : classes.classes()) known += (known.empty() ? "" : ", ") + c.name;
            throw InputError(fmt::format("unknown class '{}' (the map's classes: {})", name, known));
        }
        sel.excluded[size_t(id)] = true;
    }
    sel.floor_z = 0;
    if (o.reference == HeightReference::Floor) sel.floor_z = std::isnan(o.floor_z) ? floorHeight(map) : o.floor_z;
    sel.z_min = sel.floor_z + o.min_height;
    sel.z_max = sel.floor_z + o.max_height;
    return sel;
}

void obstaclePoints(const PanopticMap& map, const ObstacleOptions& o, mrpt::maps::CSimplePointsMap& out)
{
    const ObstacleSelection sel = resolveObstacleOptions(map, o);
    out.clear();
    forEachObstacleVoxel(map, sel, 0.0,
                         [&](uint32_t, const Eigen::Vector3d& p) { out.insertPointFast(float(p.x()), float(p.y()), float(p.z())); });
    out.mark_as_modified();
}

void obstaclePointsAround(const PanopticMap& map, const ObstacleOptions& o, const mrpt::poses::CPose3D& robot,
                          double radius, mrpt::maps::CSimplePointsMap& out)
{
    if (!(radius >= 0) || !std::isfinite(robot.x()) || !std::isfinite(robot.y()) || !std::isfinite(robot.z()) ||
        !std::isfinite(robot.yaw()) || !std::isfinite(robot.pitch()) || !std::isfinite(robot.roll()))
        throw std::invalid_argument(fmt::format("obstacle points around the robot: the pose ({}) must be finite and the "
                                                "radius ({} m) >= 0",
                                                robot.asString(), radius));
    const ObstacleSelection sel = resolveObstacleOptions(map, o);
    const double z_offset = o.reference == HeightReference::Robot ? robot.z() : 0.0;
    const double r2 = radius * radius;
    out.clear();
    forEachObstacleVoxel(map, sel, z_offset, [&](uint32_t, const Eigen::Vector3d& p) {
        const double dx = p.x() - robot.x(), dy = p.y() - robot.y();
        if (dx * dx + dy * dy > r2) return;
        double lx, ly, lz;
        robot.inverseComposePoint(p.x(), p.y(), p.z(), lx, ly, lz);
        out.insertPointFast(float(lx), float(ly), float(lz));
    });
    out.mark_as_modified();
}

}  // namespace pndt
