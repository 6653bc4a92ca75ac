// Obstacles for MRPT's reactive navigators (design §8): the NDT means of occupied
// voxels in a height band, optionally without some classes (floor, ceiling), as a
// CSimplePointsMap. Lives in the plugin so getAsSimplePointsMap() can return it;
// pndt_nav's 2D grid uses the same voxel selection.
#pragma once

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose3D.h>
#include <pndt/panoptic_map.h>

#include <limits>
#include <string>
#include <vector>

namespace pndt
{
/// What the height band is measured from.
enum class HeightReference
{
    Floor,  ///< the map's floor height (floorHeight(), or ObstacleOptions::floor_z)
    World,  ///< world z = 0
    Robot,  ///< the robot's z (obstaclePointsAround() only; elsewhere like World)
};

struct ObstacleOptions
{
    /// Band of heights (metres above the reference) whose voxels are obstacles. The
    /// defaults suit a ground robot up to 1.8 m tall: 5 cm keeps the floor's own
    /// voxel means (on the floor surface, within noise) out.
    double min_height = 0.05;
    double max_height = 1.80;
    HeightReference reference = HeightReference::Floor;
    /// Floor height in world z; NaN = estimate it from the map (floorHeight()).
    double floor_z = std::numeric_limits<double>::quiet_NaN();
    /// Class names left out (the map's class table; unknown names are an error,
    /// except "floor" and "ceiling", which a non-NYUv2 class table may lack).
    std::vector<std::string> excluded_classes{"floor", "ceiling"};

    bool operator==(const ObstacleOptions& o) const;
    bool operator!=(const ObstacleOptions& o) const { return !(*this == o); }
};

/// The floor's height in world z: the median NDT-mean z of occupied voxels whose
/// semantic label is "floor" (if the class table has one and at least 10 such
/// voxels exist); otherwise the median z of the most populated voxel layer in the
/// lower half of the occupied height range (geometry-only maps). 0 for an empty map.
double floorHeight(const PanopticMap& map);

/// Resolves options against a map: class ids to leave out and the band in world z.
struct ObstacleSelection
{
    std::vector<bool> excluded;  ///< by class id
    double z_min = 0, z_max = 0; ///< world z (Robot reference: relative to 0)
    double floor_z = 0;
};
/// Throws InputError naming an unknown class and listing the map's classes.
ObstacleSelection resolveObstacleOptions(const PanopticMap& map, const ObstacleOptions& o);

/// Calls visit(voxel index, NDT mean) for every occupied voxel in the band whose
/// class (the semantic part of its propagated label, so label-filled voxels count
/// with their filled class) is not excluded. `z_offset` shifts the band (robot height).
template <class Visit>
void forEachObstacleVoxel(const PanopticMap& map, const ObstacleSelection& sel, double z_offset, Visit&& visit)
{
    const VoxelStore& store = map.voxels();
    for (uint32_t i = 0; i < store.size(); ++i)
    {
        const Voxel& v = store[i];
        if (!map.isOccupied(v)) continue;
        const Eigen::Vector3d p = map.pointOf(i);
        if (p.z() < sel.z_min + z_offset || p.z() > sel.z_max + z_offset) continue;
        const uint16_t c = map.panopticLabel(i).semantic;
        if (c < sel.excluded.size() && sel.excluded[c]) continue;
        visit(i, p);
    }
}

/// Obstacle points in world coordinates (replaces `out`'s contents).
void obstaclePoints(const PanopticMap& map, const ObstacleOptions& o, mrpt::maps::CSimplePointsMap& out);

/// Obstacle points within `radius` (xy) of the robot, in the robot's local frame:
/// what CRobot2NavInterface::senseObstacles() must return. With
/// HeightReference::Robot the band is measured from the robot's z.
void obstaclePointsAround(const PanopticMap& map, const ObstacleOptions& o, const mrpt::poses::CPose3D& robot,
                          double radius, mrpt::maps::CSimplePointsMap& out);

}  // namespace pndt
