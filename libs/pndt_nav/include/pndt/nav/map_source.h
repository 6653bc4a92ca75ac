// Where pndt-nav gets its map: a .pndt.gz file, or the newest short-term map in
// a pndt-map output folder (reloaded when a newer one appears).
#pragma once

#include <pndt/mrpt/PanopticNDTMap.h>

#include <filesystem>
#include <string>

namespace pndt::nav
{
/// The newest `*.pndt.gz` in `dir` (by modification time, then by name: pndt-map
/// numbers its maps). Throws InputError if there is none.
std::filesystem::path newestMapFile(const std::filesystem::path& dir);

struct LoadedMap
{
    PanopticNDTMap::Ptr map;
    std::filesystem::path file;
    std::filesystem::file_time_type stamp{};
};

/// `path` is a map file or a folder of them. Throws InputError (missing file,
/// empty folder, unreadable or foreign archive) naming the path.
LoadedMap loadNavigationMap(const std::filesystem::path& path);

/// For a folder: true (and `current` replaced) when a newer map than `current`
/// has appeared. A file source never changes.
bool reloadIfNewer(const std::filesystem::path& source, LoadedMap& current);

}  // namespace pndt::nav
