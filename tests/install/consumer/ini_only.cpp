// An outside program that uses only MRPT's API: the map comes from an .ini, and the program
// links PanopticNDT::mrpt as the README says, without naming a pndt symbol. Debian's gcc links
// --as-needed, which dropped the plugin: MRPT then made the multi-map without it, silently.
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>

#include <cstdio>

int main()
{
    mrpt::config::CConfigFileMemory ini(
        "[MAP]\nPanopticNDTMap_count=1\n[MAP_PanopticNDTMap_00_creationOpts]\nvoxel_size=0.10\n");
    mrpt::maps::TSetOfMetricMapInitializers defs;
    defs.loadFromConfigFile(ini, "MAP");
    mrpt::maps::CMultiMetricMap maps;
    maps.setListOfMaps(defs);
    if (maps.maps.size() != 1 || std::string(maps.maps[0]->GetRuntimeClass()->className) != "pndt::PanopticNDTMap")
    {
        std::fprintf(stderr, "ini_only: the multi-map holds %zu maps, not the PanopticNDTMap (plugin not loaded)\n",
                     maps.maps.size());
        return 1;
    }
    std::printf("ini_only: the .ini made a %s\n", maps.maps[0]->GetRuntimeClass()->className);
    return 0;
}
