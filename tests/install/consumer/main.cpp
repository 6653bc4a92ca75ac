// A program of a user's own against the installed library: builds a map from a few generated
// frames with the core API, and a PanopticNDTMap from an .ini through MRPT's CMultiMetricMap.
// Exit 0 only if both hold what they should.
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <pndt/build_config.h>
#include <pndt/mrpt/PanopticNDTMap.h>
#include <pndt/panoptic_map.h>

#include <cstdio>

int main()
{
    // A wall 2 m ahead with a 20x20-pixel box of instance 1 (chair) at 1.5 m.
    pndt::PanopticFrame f;
    f.K = {64, 48, 50, 50, 31.5, 23.5};
    f.depth = pndt::Image<float>(64, 48, 2.f);
    f.semantic = pndt::Image<uint16_t>(64, 48, 1);  // wall
    f.semantic_score = pndt::Image<float>(64, 48, 0.9f);
    f.instance = pndt::Image<uint32_t>(64, 48, 0);
    f.panoptic_score = pndt::Image<float>(64, 48, 0.f);
    for (int r = 14; r < 34; ++r)
        for (int c = 22; c < 42; ++c)
        {
            f.depth.at(r, c) = 1.5f;
            f.semantic.at(r, c) = 5;  // chair
            f.instance.at(r, c) = 1;
            f.panoptic_score.at(r, c) = 0.8f;
        }
    pndt::MapOptions o;
    o.voxel_size = 0.05;
    pndt::PanopticMap map(o);
    for (int i = 0; i < 5; ++i)
    {
        pndt::Pose T = pndt::Pose::Identity();
        T.translation().x() = 0.01 * i;
        map.integrate(f, T);
    }
    const size_t occupied = map.occupiedCount();
    const auto instances = map.instances();
    std::printf("core: %zu occupied voxels, %zu instances (quantised histograms: %d)\n", occupied, instances.size(),
                PNDT_QUANTISED_HISTOGRAMS);

    mrpt::config::CConfigFileMemory ini(
        "[MAP]\nPanopticNDTMap_count=1\n[MAP_PanopticNDTMap_00_creationOpts]\nvoxel_size=0.10\n");
    mrpt::maps::TSetOfMetricMapInitializers defs;
    defs.loadFromConfigFile(ini, "MAP");
    mrpt::maps::CMultiMetricMap maps;
    maps.setListOfMaps(defs);
    const bool plugin = bool(maps.mapByClass<pndt::PanopticNDTMap>());
    std::printf("mrpt: PanopticNDTMap from the .ini: %s\n", plugin ? "yes" : "no");
    return occupied > 100 && instances.size() == 1 && instances[0].semantic == 5 && plugin ? 0 : 1;
}
