// Registers the plugin's classes with MRPT when the library is loaded
// (normal linking, dlopen by MRPT tools, or LD_PRELOAD).
#include <mrpt/core/initializer.h>
#include <pndt/mrpt/CObservationPanopticMap.h>
#include <pndt/mrpt/PanopticNDTMap.h>

MRPT_INITIALIZER(register_pndt_classes)
{
    mrpt::rtti::registerClass(CLASS_ID(pndt::PanopticNDTMap));
    mrpt::rtti::registerClass(CLASS_ID(pndt::CObservationPanopticMap));  // maps.rawlog entries
}

// The CMultiMetricMap factory ("PanopticNDTMap_count=1" in an .ini).
MAP_DEFINITION_REGISTER("pndt::PanopticNDTMap,PanopticNDTMap", pndt::PanopticNDTMap)
