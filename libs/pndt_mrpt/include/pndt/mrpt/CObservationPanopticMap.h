// A finished short-term map as an MRPT observation, so a stream of maps is a
// rawlog that MRPT's own tools (rawlog-edit -p, RawLogViewer -l) list, cut and
// show over time (issue #21). Registered by the plugin (register.cpp).
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>
#include <pndt/mrpt/PanopticNDTMap.h>

#include <cstdint>

namespace pndt
{
class CObservationPanopticMap : public mrpt::obs::CObservation
{
    DEFINE_SERIALIZABLE(CObservationPanopticMap, pndt)

   public:
    /// Default label of the maps' stream (pndt-map's maps_rawlog_label).
    static constexpr const char* kDefaultLabel = "PANOPTIC_MAP";

    CObservationPanopticMap() { sensorLabel = kDefaultLabel; }

    /// The map (read only once handed over; shared with its other writers).
    /// Serialised as a whole MRPT object, i.e. with PanopticNDTMap's own version.
    PanopticNDTMap::Ptr map;
    /// The map is in world coordinates: the "sensor" sits at the world origin.
    mrpt::poses::CPose3D sensorPose;
    /// Sensor time of the map's first frame (`timestamp` is its last: the hand-over).
    mrpt::system::TTimeStamp start = INVALID_TIMESTAMP;
    uint64_t frames = 0;    ///< frames integrated into the map
    uint32_t sequence = 0;  ///< number of the map in its run (map_NNNN)

    void getSensorPose(mrpt::poses::CPose3D& out) const override { out = sensorPose; }
    void setSensorPose(const mrpt::poses::CPose3D& p) override { sensorPose = p; }
    /// The base description, the map's span and size, then occupied voxels and
    /// instances per class (propagated labels).
    void getDescriptionAsText(std::ostream& o) const override;
};

}  // namespace pndt
