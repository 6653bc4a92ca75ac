// Where the apps find their configuration, and the short-term maps it defines.
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <pndt/app/short_term_maps.h>

#include <string>

namespace pndt::app
{
/// $PNDT_CONFIG_DIR, else an installed copy (<prefix>/share/panopticndt/config beside
/// <prefix>/bin/<app>), else `source_tree_config` (the build tree's config/).
std::string configDir(const std::string& source_tree_config);

/// Factory of fresh maps from the [MAP] section's PanopticNDTMap definition; throws
/// std::invalid_argument naming a [MAP] key other than <map class>_count or another map, and
/// if [MAP] defines none.
ShortTermMaps::Factory mapFactory(const mrpt::config::CConfigFileBase& cfg);
}  // namespace pndt::app
