// JSON output (nav_json.h).
#include <pndt/nav/nav_json.h>

namespace pndt::nav
{
namespace
{
nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
nlohmann::json vec(const Eigen::Vector2d& v) { return {v.x(), v.y()}; }
}  // namespace

nlohmann::json toJson(const MapObject& o)
{
    return {{"id", o.id},
            {"instance_id", o.instance_id},
            {"class_id", o.class_id},
            {"class", o.class_name},
            {"voxels", o.voxel_count},
            {"centroid", vec(o.centroid)},
            {"bbox_min", vec(o.bbox_min)},
            {"bbox_max", vec(o.bbox_max)},
            {"footprint",
             {{"center", vec(o.footprint.center)}, {"yaw", o.footprint.yaw}, {"half_size", vec(o.footprint.half_size)}}},
            {"z_range", {o.z_min, o.z_max}},
            {"pieces", o.pieces},
            {"class_confidence", o.class_confidence},
            {"instance_confidence", o.instance_confidence},
            {"instance_updates", o.instance_updates},
            {"frames_seen", o.frames_seen},
            {"confidence", o.confidence},
            {"source", o.source}};
}

nlohmann::json toJson(const std::vector<MapObject>& objects)
{
    nlohmann::json a = nlohmann::json::array();
    for (const MapObject& o : objects) a.push_back(toJson(o));
    return a;
}

nlohmann::json toJson(const QueryResult& r)
{
    nlohmann::json matches = nlohmann::json::array();
    for (const QueryMatch& m : r.matches)
    {
        nlohmann::json j = {{"id", m.object->id}, {"class", m.object->class_name}, {"related", m.related}};
        if (r.kind == QueryKind::Nearest) j["distance"] = m.distance;
        if (r.kind == QueryKind::MostAround || r.kind == QueryKind::FewestAround || r.kind == QueryKind::CountAround ||
            r.kind == QueryKind::HasAround)
            j["count"] = m.related.size();
        matches.push_back(j);
    }
    nlohmann::json j = {{"query", r.query}, {"kind", toString(r.kind)}, {"target_class", r.target_class},
                        {"related_class", r.related_class}, {"matches", matches}, {"summary", r.summary}};
    if (r.kind == QueryKind::CountAround) j["count"] = r.count;
    if (r.kind == QueryKind::Nearest) j["point"] = vec(r.point);
    j["best"] = r.best() ? nlohmann::json(r.best()->id) : nlohmann::json(nullptr);
    return j;
}

nlohmann::json toJson(const GoalPose& g)
{
    nlohmann::json j = {{"found", g.found}, {"object_id", g.object_id}, {"candidates", g.candidates}};
    if (g.found)
    {
        j["pose"] = {g.x, g.y, g.yaw};
        j["clearance"] = g.clearance;
        j["distance_to_object"] = g.distance_to_object;
    }
    else
        j["reason"] = g.reason;
    return j;
}

nlohmann::json toJson(const NavigationGrid& g)
{
    return {{"size", {g.grid.getSizeX(), g.grid.getSizeY()}},
            {"origin", {g.grid.getXMin(), g.grid.getYMin()}},
            {"resolution", g.grid.getResolution()},
            {"floor_z", g.floor_z},
            {"cells", {{"free", g.free_cells}, {"occupied", g.occupied_cells}, {"unknown", g.unknown_cells}}}};
}

}  // namespace pndt::nav
