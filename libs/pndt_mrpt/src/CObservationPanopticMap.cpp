// Serialisation, version 0: sensorLabel, timestamp, sensorPose, start (stamp),
// frames (u64), sequence (u32), a flag for the map (bool), then the map as an
// MRPT object (class name + PanopticNDTMap's own version + data).
#include <fmt/format.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>
#include <pndt/mrpt/CObservationPanopticMap.h>

#include <map>

namespace pndt
{
IMPLEMENTS_SERIALIZABLE(CObservationPanopticMap, CObservation, pndt)

uint8_t CObservationPanopticMap::serializeGetVersion() const { return 0; }

void CObservationPanopticMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    out << sensorLabel << timestamp << sensorPose << start << frames << sequence;
    out << bool(map);
    if (map) out << *map;
}

void CObservationPanopticMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    switch (version)
    {
        case 0:
        {
            uint8_t has_map = 0;  // a bool, read as its byte: MRPT's bool reader takes any value
            in >> sensorLabel >> timestamp >> sensorPose >> start >> frames >> sequence >> has_map;
            if (has_map > 1) throw std::runtime_error(fmt::format("the has-map flag is a bool holding {}", has_map));
            map.reset();
            if (has_map) map = in.ReadObject<PanopticNDTMap>();
            break;
        }
        default: MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    }
}

void CObservationPanopticMap::getDescriptionAsText(std::ostream& o) const
{
    CObservation::getDescriptionAsText(o);
    o << fmt::format("Short-term panoptic map #{}: {} frames", sequence, frames);
    if (start != INVALID_TIMESTAMP && timestamp != INVALID_TIMESTAMP)
        o << fmt::format(", {:.3f} s from {:.6f} to {:.6f} (hand-over)",
                         mrpt::system::timeDifference(start, timestamp), mrpt::Clock::toDouble(start),
                         mrpt::Clock::toDouble(timestamp));
    o << "\n";
    if (!map)
    {
        o << "(no map)\n";
        return;
    }
    o << map->asString() << "\n";
    const PanopticMap& m = map->core();
    m.finalize();
    const ClassSet& classes = m.options().classes;
    struct Count
    {
        uint64_t voxels = 0, instances = 0;
    };
    std::map<uint32_t, Count> per_class;
    uint64_t void_voxels = 0;
    const uint32_t n = uint32_t(m.voxels().size());
    for (uint32_t i = 0; i < n; ++i)
    {
        if (!m.isOccupied(m.voxels()[i])) continue;
        const PanopticLabel l = m.panopticLabel(i);
        if (l.semantic == 0)
            ++void_voxels;
        else
            ++per_class[l.semantic].voxels;
    }
    for (const MapInstance& inst : m.instances()) ++per_class[inst.semantic].instances;
    o << fmt::format("{:<24} {:>10} {:>10}\n", "class", "voxels", "instances");
    for (const auto& [c, k] : per_class)
        o << fmt::format("{:<24} {:>10} {:>10}\n",
                         classes.contains(c) ? fmt::format("{} {}", c, classes.name(c)) : fmt::format("{} ?", c),
                         k.voxels, k.instances);
    o << fmt::format("{:<24} {:>10}\n", "(no label)", void_voxels);
}

}  // namespace pndt

// Registered with MRPT's class registry here, by a static object after the class id: the
// class id holds a std::function, built by this file's dynamic initialisation, which runs in
// the order of definitions. MRPT_INITIALIZER (__attribute__((constructor))) may run before it
// and registered a null name (seen with clang).
namespace
{
[[maybe_unused]] const bool kRegisteredCObservationPanopticMap = [] {
    mrpt::rtti::registerClass(CLASS_ID(pndt::CObservationPanopticMap));
    return true;
}();
}  // namespace
