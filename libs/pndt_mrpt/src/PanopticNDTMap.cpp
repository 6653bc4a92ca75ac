// PanopticNDTMap: observation pairing and the CMetricMap basics.
#include <fmt/format.h>
#include <mrpt/system/datetime.h>
#include <pndt/mrpt/PanopticNDTMap.h>
#include <pndt/refine/pose_refiner.h>
#include <pndt/mrpt/observation_frame.h>

#include <cmath>

using mrpt::obs::CObservation3DRangeScan;
using mrpt::obs::CObservationImage;

namespace pndt
{
IMPLEMENTS_SERIALIZABLE(PanopticNDTMap, CMetricMap, pndt)

PanopticNDTMap::PanopticNDTMap(const MapOptions& options) : insertionOptions(pairer_.options), map_(options) {}

PanopticNDTMap::PanopticNDTMap(const PanopticNDTMap& o)
    : mrpt::maps::CMetricMap(o),
      insertionOptions(pairer_.options),
      renderOptions(o.renderOptions),
      navigationOptions(o.navigationOptions),
      map_(o.map_),
      pairer_(o.pairer_),
      stats_(o.stats_)
{
}

PanopticNDTMap& PanopticNDTMap::operator=(const PanopticNDTMap& o)
{
    if (this == &o) return *this;
    mrpt::maps::CMetricMap::operator=(o);
    renderOptions = o.renderOptions;
    navigationOptions = o.navigationOptions;
    map_ = o.map_;
    pairer_ = o.pairer_;
    stats_ = o.stats_;
    refiner_.reset();  // as a copy does: its own refiner from its next refined frame
    return *this;
}

void PanopticNDTMap::internal_clear()
{
    map_.clear();
    pairer_.clear();
    stats_ = {};
    refiner_.reset();  // its carried correction was against the map just cleared
}

bool PanopticNDTMap::isEmpty() const { return map_.voxels().empty(); }

Pose PanopticNDTMap::refinedPose(const FrameView& frame, const Pose& T_world_cam)
{
    if (!insertionOptions.refine_pose) return T_world_cam;
    if (!refiner_)
    {
        refine::RefineOptions ro;
        ro.enabled = true;
        ro.thing_weight = insertionOptions.refine_thing_weight;
        ro.loss_scale = insertionOptions.refine_loss_scale;
        refiner_ = std::make_shared<refine::PoseRefiner>(ro);
    }
    return refiner_->refine(map_, frame, T_world_cam).pose;
}

FrameStats PanopticNDTMap::integrate(const PanopticFrame& frame, const Pose& T_world_cam)
{
    const FrameStats st = map_.integrate(frame, refinedPose(FrameView(frame), T_world_cam));
    stats_.totals += st;
    return st;
}

FrameStats PanopticNDTMap::integrate(const FrameView& frame, const Pose& T_world_cam)
{
    const FrameStats st = map_.integrate(frame, refinedPose(frame, T_world_cam));
    stats_.totals += st;
    return st;
}

void PanopticNDTMap::integratePaired()
{
    for (const PairedFrame& p : paired_)
    {
        integrate(p.frame, p.T_world_cam);
        ++(p.labelled ? stats_.frames_with_labels : stats_.frames_geometry_only);
    }
    if (!paired_.empty()) pairer_.recycle(std::move(paired_.back()));  // its images take the next scan
    paired_.clear();
    stats_.label_images_dropped = pairer_.labelImagesDropped();
}

bool PanopticNDTMap::internal_insertObservation(const mrpt::obs::CObservation& obs,
                                                const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
    paired_.clear();
    const bool used = pairer_.push(obs, robotPose ? *robotPose : mrpt::poses::CPose3D(), paired_);
    integratePaired();
    return used;
}

void PanopticNDTMap::flushPending()
{
    pairer_.flush(paired_);
    integratePaired();
}

std::string PanopticNDTMap::asString() const
{
    const auto& o = map_.options();
    return fmt::format("PanopticNDTMap: voxel {:.3f} m, {} voxels ({} occupied), {} instances, {} mode, {} classes",
                       o.voxel_size, map_.voxels().size(), map_.occupiedCount(), map_.instances().size(),
                       o.use_ndt ? "NDT" : "cube", o.classes.size());
}

// Likelihood, obstacles, matching: PanopticNDTMap_navigation.cpp.

}  // namespace pndt

// Registered with MRPT's class registry here, by a static object after the class id: the
// class id holds a std::function, built by this file's dynamic initialisation, which runs in
// the order of definitions. MRPT_INITIALIZER (__attribute__((constructor))) may run before it
// and registered a null name (seen with clang).
namespace
{
[[maybe_unused]] const bool kRegisteredPanopticNDTMap = [] {
    mrpt::rtti::registerClass(CLASS_ID(pndt::PanopticNDTMap));
    return true;
}();
}  // namespace
