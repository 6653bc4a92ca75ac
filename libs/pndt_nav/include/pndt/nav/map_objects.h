// The map's instances as objects a navigation app can ask about: class, where
// (centroid, oriented footprint, height range), how big, how sure.
#pragma once

#include <pndt/nav/footprint.h>
#include <pndt/panoptic_map.h>

#include <string>
#include <vector>

namespace pndt::nav
{
/// Object ids of pieces split off an instance: instance id + k * kSplitIdStep.
constexpr uint32_t kSplitIdStep = 1u << 24;

struct ObjectOptions
{
    /// A connected piece of an instance, apart from its largest, becomes an object
    /// of its own when it has at least this many voxels and this share of the
    /// largest piece, and its footprint does not overlap the largest piece's: the map's matching sometimes gives two objects of one class one id
    /// (two tables 2 m apart). A round table's foot under its top stays with it.
    uint32_t split_min_voxels = 20;
    double split_min_share = 0.3;
};

struct MapObject
{
    uint32_t id = 0;           ///< the map instance id; pieces split off it: + k * kSplitIdStep
    uint32_t instance_id = 0;  ///< the map instance it comes from
    uint16_t class_id = 0;
    std::string class_name;
    uint32_t voxel_count = 0;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< mean of its voxels' NDT means
    Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero(), bbox_max = Eigen::Vector3d::Zero();
    /// Smallest rectangle around the NDT means of its largest connected piece of
    /// voxels, half a voxel added per side (means lie on the surface, up to half
    /// a voxel inside the object's edge).
    Footprint footprint;
    double z_min = 0, z_max = 0;  ///< of that piece's means
    /// 26-connected pieces its instance's voxels form (1 = one solid object; more =
    /// stray voxels with its id elsewhere, left out of footprint and heights, or
    /// large pieces split off as objects of their own: ObjectOptions).
    uint32_t pieces = 1;
    /// Share of its voxels' semantic mass (h^L) on its class: how sure the class is.
    double class_confidence = 0;
    /// Share of its voxels' instance mass (h^Z) on its id: how clearly the voxels belong to it.
    double instance_confidence = 0;
    /// Pixel updates of its voxels' instance histograms (sum of n^Z): how much it was seen.
    uint64_t instance_updates = 0;
    /// Frames in which a prediction was matched to its instance or created it (0
    /// in maps written before the map counted them).
    uint32_t frames_seen = 0;
    /// The map's score of the instance: weight share x (1 - exp(-frames_seen / 3))
    /// (MapInstance::confidence); what to sort candidates by.
    double confidence = 0;
    /// The short-term map file it came from (empty for a map being built).
    std::string source;
};

/// Every instance of the map (after propagation), by id; large separate pieces of
/// one instance as objects of their own (ObjectOptions). Objects smaller than
/// `min_voxels` are left out (fragments).
std::vector<MapObject> mapObjects(const PanopticMap& map, const std::string& source = "", uint32_t min_voxels = 1,
                                  const ObjectOptions& options = {});

/// The object with this id, or nullptr.
const MapObject* findObject(const std::vector<MapObject>& objects, uint32_t id);

/// A class id from a name in the map's class table ("chair", "chairs", "night stand",
/// or a number); -1 if unknown. Plurals: -s, -es, -ves (-> f), -ies (-> y).
int classIdFromName(const ClassSet& classes, const std::string& name);

}  // namespace pndt::nav
