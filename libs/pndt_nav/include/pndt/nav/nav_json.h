// JSON for what pndt_nav computes (apps write it; a navigation app reads it).
#pragma once

#include <nlohmann/json.hpp>
#include <pndt/nav/goal_pose.h>
#include <pndt/nav/navigation_grid.h>
#include <pndt/nav/object_query.h>

namespace pndt::nav
{
nlohmann::json toJson(const MapObject& o);
nlohmann::json toJson(const std::vector<MapObject>& objects);
nlohmann::json toJson(const QueryResult& r);
nlohmann::json toJson(const GoalPose& g);
/// Size, origin, resolution and cell counts (not the cells).
nlohmann::json toJson(const NavigationGrid& g);

}  // namespace pndt::nav
