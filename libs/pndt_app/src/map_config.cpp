#include <mrpt/maps/TMetricMapInitializer.h>
#include <pndt/app/map_config.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>

namespace pndt::app
{
std::string configDir(const std::string& source_tree_config)
{
    if (const char* d = std::getenv("PNDT_CONFIG_DIR")) return d;
    std::error_code ec;
    const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec)
    {
        const auto installed = exe.parent_path().parent_path() / "share" / "panopticndt" / "config";
        if (std::filesystem::is_regular_file(installed / "panoptic_ndt.ini")) return installed.string();
    }
    return source_tree_config;
}

ShortTermMaps::Factory mapFactory(const mrpt::config::CConfigFileBase& cfg)
{
    auto inits = std::make_shared<mrpt::maps::TSetOfMetricMapInitializers>();
    inits->loadFromConfigFile(cfg, "MAP");
    for (const auto& def : *inits)
        if (def->getMetricMapClassType() == CLASS_ID(PanopticNDTMap))
            return [inits, def] { return PanopticNDTMap::Ptr(PanopticNDTMap::CreateFromMapDefinition(*def)); };
    throw std::runtime_error("config: [MAP] defines no PanopticNDTMap (set PanopticNDTMap_count=1)");
}
}  // namespace pndt::app
