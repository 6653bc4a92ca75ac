// Spatial relations between map objects, from their footprints and heights:
// on top of, next to, around (chairs around a table), nearest to a point.
#pragma once

#include <pndt/nav/map_objects.h>

#include <map>
#include <vector>

namespace pndt::nav
{
struct RelationOptions
{
    /// On top of: the upper object's bottom within this of the lower one's top (m).
    double on_top_z_tolerance = 0.15;
    /// Next to: footprints at most this far apart (m).
    double next_to_distance = 0.5;
    /// Around: footprints at most this far apart (m). Chairs pushed under a table
    /// overlap it (distance 0); a chair pulled out stands ~0.3 m off.
    double around_distance = 0.6;
};

/// `upper` rests on `lower`: its bottom is at the lower one's top and its centre
/// lies over the lower one's footprint.
bool isOnTopOf(const MapObject& upper, const MapObject& lower, const RelationOptions& o = {});
/// Footprints within next_to_distance, heights overlapping, neither on the other.
bool isNextTo(const MapObject& a, const MapObject& b, const RelationOptions& o = {});

/// Two objects of one class that are pieces of one thing (a chair whose back the
/// network saw as another chair instance): one's footprint centre lies inside
/// the other's footprint (more than half of it overlaps: two real chairs never do).
bool areFragmentsOfOne(const MapObject& a, const MapObject& b);

/// Objects of `around_class` around each object of `center_class`: each
/// candidate within around_distance counts for the nearest such centre only (a
/// chair between two tables is counted once), and fragments of one object
/// (areFragmentsOfOne) count once, as their largest piece. Keyed by centre id;
/// every centre is present (possibly with none).
std::map<uint32_t, std::vector<uint32_t>> objectsAround(const std::vector<MapObject>& objects, int center_class,
                                                        int around_class, const RelationOptions& o = {});

/// Objects of `class_id` (-1 = any) by distance of their footprint to `p`, nearest first.
std::vector<std::pair<const MapObject*, double>> nearestTo(const std::vector<MapObject>& objects, int class_id,
                                                           const Eigen::Vector2d& p);

}  // namespace pndt::nav
