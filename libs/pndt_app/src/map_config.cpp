#include <fmt/format.h>
#include <mrpt/maps/TMetricMapInitializer.h>
#include <mrpt/maps/TMetricMapTypesRegistry.h>
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

namespace
{
/// [MAP] as the apps use it: MRPT reads only `<map class>_count` keys there and ignores any
/// other, and the apps build one PanopticNDTMap and nothing else, so a typo or another map
/// would be silently dropped.
void checkMapSection(const mrpt::config::CConfigFileBase& cfg)
{
    std::vector<std::string> keys;
    cfg.getAllKeys("MAP", keys);
    const auto& registered = mrpt::maps::internal::TMetricMapTypesRegistry::Instance().getAllRegistered();
    const std::string tail = "_count";
    for (const auto& key : keys)
    {
        const bool count = key.size() > tail.size() && key.compare(key.size() - tail.size(), tail.size(), tail) == 0;
        const std::string map = count ? key.substr(0, key.size() - tail.size()) : std::string();
        if (!count || !registered.count(map))
            throw std::invalid_argument(fmt::format(
                "config [MAP]: unknown key '{}' (the section holds <map class>_count keys, e.g. PanopticNDTMap_count=1)",
                key));
        const std::string value = cfg.read_string("MAP", key, "0");
        const bool ours = map == "PanopticNDTMap" || map == "pndt::PanopticNDTMap";
        if (value != "0" && value != (ours ? "1" : "0"))
            throw std::invalid_argument(fmt::format("config [MAP]: {}={}: the apps build one PanopticNDTMap and no "
                                                    "other map (PanopticNDTMap_count=1 and nothing else)",
                                                    key, value));
    }
}
}  // namespace

ShortTermMaps::Factory mapFactory(const mrpt::config::CConfigFileBase& cfg)
{
    checkMapSection(cfg);
    auto inits = std::make_shared<mrpt::maps::TSetOfMetricMapInitializers>();
    inits->loadFromConfigFile(cfg, "MAP");
    for (const auto& def : *inits)
        if (def->getMetricMapClassType() == CLASS_ID(PanopticNDTMap))
            return [inits, def] { return PanopticNDTMap::Ptr(PanopticNDTMap::CreateFromMapDefinition(*def)); };
    throw std::runtime_error("config: [MAP] defines no PanopticNDTMap (set PanopticNDTMap_count=1)");
}
}  // namespace pndt::app
