// Registers the map with CMultiMetricMap's factory when the library is loaded (normal
// linking, dlopen by MRPT tools, or LD_PRELOAD). The classes register themselves with
// MRPT's class registry in their own files (PanopticNDTMap.cpp, CObservationPanopticMap.cpp).
#include <pndt/mrpt/PanopticNDTMap.h>

// The CMultiMetricMap factory ("PanopticNDTMap_count=1" in an .ini).
MAP_DEFINITION_REGISTER("pndt::PanopticNDTMap,PanopticNDTMap", pndt::PanopticNDTMap)
