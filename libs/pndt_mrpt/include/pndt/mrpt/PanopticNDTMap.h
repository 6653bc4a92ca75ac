// pndt::PanopticNDTMap: the panoptic occupancy NDT map as an MRPT metric map.
// Build it from an .ini through CMultiMetricMap (`PanopticNDTMap_count=1`),
// feed it CObservation3DRangeScan + the two float32 panoptic CObservationImage
// (design §5) in either order, serialise it with MRPT archives.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <memory>
#include <mrpt/maps/CMetricMap.h>
#include <mrpt/maps/TMetricMapTypesRegistry.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/poses/CPose3D.h>
#include <pndt/mrpt/obstacle_cache.h>
#include <pndt/mrpt/observation_pairer.h>
#include <pndt/mrpt/scan_likelihood.h>
#include <pndt/panoptic_map.h>

#include <deque>
#include <optional>

namespace pndt::refine
{
class PoseRefiner;
}
namespace pndt
{
enum class ColorMode
{
    Semantic,
    Instance,
    Panoptic
};
enum class VoxelShape
{
    Points,      ///< one coloured point per NDT mean
    Ellipsoids,  ///< NDT Gaussians
    Cubes        ///< voxel cubes (the "w/o NDT" view)
};

struct RenderOptions : public mrpt::config::CLoadableOptions
{
    ColorMode color_mode = ColorMode::Panoptic;
    VoxelShape shape = VoxelShape::Points;
    bool show_free = false;
    float point_size = 3.0f;
    size_t max_ellipsoids = 20000;  ///< beyond this, fall back to points
    double ellipsoid_quantile = 2.0;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& section) override;
    void dumpToTextStream(std::ostream& out) const override;
};

/// Counters of the observation pairing, reset by clear().
struct InsertionStats
{
    uint64_t frames_with_labels = 0;
    uint64_t frames_geometry_only = 0;   ///< depth with no labels within the tolerance
    uint64_t label_images_dropped = 0;   ///< never met their depth frame
    FrameStats totals;
};

/// What the navigation side of the map uses (PanopticNDTMap_navigation.cpp).
/// Settings of the navigator, not of the map: not serialised.
struct NavigationOptions
{
    ObstacleOptions obstacles;    ///< getAsSimplePointsMap()
    LikelihoodOptions likelihood; ///< computeObservationLikelihood()
};

class PanopticNDTMap : public mrpt::maps::CMetricMap
{
    DEFINE_SERIALIZABLE(PanopticNDTMap, pndt)

   public:
    explicit PanopticNDTMap(const MapOptions& options = {});

    InsertionOptions& insertionOptions;  ///< the pairer's options
    RenderOptions renderOptions;
    NavigationOptions navigationOptions;

    const PanopticMap& core() const { return map_; }
    PanopticMap& core() { return map_; }
    const InsertionStats& insertionStats() const { return stats_; }

    /// Maps a depth frame still waiting for labels (geometry only). Call at the
    /// end of a stream; queries and serialisation see only integrated frames.
    void flushPending();
    bool hasPending() const { return pairer_.hasPending(); }

    /// Integrates one already-assembled frame (bypassing observation pairing).
    FrameStats integrate(const PanopticFrame& frame, const Pose& T_world_cam);
    /// The same over the caller's buffers, e.g. frameViewOf(scan) for a range scan's
    /// uint16 image read in place (pndt/frame.h).
    FrameStats integrate(const FrameView& frame, const Pose& T_world_cam);

    // CMetricMap
    bool isEmpty() const override;
    void saveMetricMapRepresentationToFile(const std::string& prefix) const override;
    void getVisualizationInto(mrpt::opengl::CSetOfObjects& outObj) const override;
    std::string asString() const override;

    // CMetricMap for navigation and localisation (PanopticNDTMap_navigation.cpp)
    /// Obstacle points (navigationOptions.obstacles), world frame; cached until the map changes.
    const mrpt::maps::CSimplePointsMap* getAsSimplePointsMap() const override;
    using mrpt::maps::CMetricMap::getAsSimplePointsMap;
    /// Share of the other map's points (at otherMapPose) within
    /// params.maxMahaDistForCorr (Mahalanobis) of a Gaussian.
    float compute3DMatchingRatio(const mrpt::maps::CMetricMap* otherMap, const mrpt::poses::CPose3D& otherMapPose,
                                 const mrpt::maps::TMatchingRatioParams& params) const override;
    /// Squared 2D distance to the nearest obstacle point (infinity-like 1e10 if none).
    float squareDistanceToClosestCorrespondence(float x0, float y0) const override;

    MAP_DEFINITION_START(PanopticNDTMap)
    MapOptions map_options;
    InsertionOptions insertionOpts;
    RenderOptions renderOpts;
    MAP_DEFINITION_END(PanopticNDTMap)

   protected:
    void internal_clear() override;
    bool internal_insertObservation(const mrpt::obs::CObservation& obs,
                                    const std::optional<const mrpt::poses::CPose3D>& robotPose) override;
    double internal_computeObservationLikelihood(const mrpt::obs::CObservation& obs,
                                                 const mrpt::poses::CPose3D& takenFrom) const override;
    bool internal_canComputeObservationLikelihood(const mrpt::obs::CObservation& obs) const override;
    void OnPostSuccesfulInsertObs(const mrpt::obs::CObservation&) override;

   public:
    PanopticNDTMap(const PanopticNDTMap& o);
    PanopticNDTMap& operator=(const PanopticNDTMap& o);

   private:
    void integratePaired();

    PanopticMap map_;
    ObservationPairer pairer_;
    std::vector<PairedFrame> paired_;  ///< reused between observations
    InsertionStats stats_;
    mutable ObstacleCache obstacle_cache_;
    /// insertionOptions.refine_pose: created at the first refined frame; a copy (or an assigned
    /// map) starts its own, and clear() drops it with the map its correction was estimated on.
    std::shared_ptr<refine::PoseRefiner> refiner_;
    /// T_world_cam registered to the map when insertionOptions.refine_pose (both integrate paths).
    Pose refinedPose(const FrameView& frame, const Pose& T_world_cam);

   public:
    /// The pose refiner (insertionOptions.refine_pose), nullptr before the first refined frame.
    const refine::PoseRefiner* refiner() const { return refiner_.get(); }
};

/// Reads all PanopticNDTMap options from an MRPT config source, rejecting any key
/// that is not an option (the error names the section and the key).
void loadMapOptions(const mrpt::config::CConfigFileBase& c, const std::string& section, MapOptions& o);
void dumpMapOptions(const MapOptions& o, std::ostream& out);

}  // namespace pndt
