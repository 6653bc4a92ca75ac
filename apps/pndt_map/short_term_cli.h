// --max-voxels / --keep-maps / --maps-rawlog-segment of pndt-map and pndt-live: what bounds a
// long run's map memory and the map files on disk (config [pndt-map] max_voxels, keep_maps,
// maps_rawlog_segment; doc/hardening.md).
#pragma once

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pndt::app
{
struct ShortTermCli
{
    std::optional<uint64_t> max_voxels, keep_maps, maps_rawlog_segment;

    void addTo(CLI::App& app)
    {
        const CLI::Validator count(
            [](std::string& v) { return !v.empty() && v[0] == '-' ? std::string("must be 0 or more") : std::string(); },
            "N >= 0");
        app.add_option("--max-voxels", max_voxels,
                       "size budget of one map in voxels: a map reaching it is written and a new one started (0 = "
                       "none; config max_voxels)")
            ->check(count);
        app.add_option("--keep-maps", keep_maps,
                       "map files kept on disk: older ones are deleted and leave index.json (0 = all; config keep_maps)")
            ->check(count);
        app.add_option("--maps-rawlog-segment", maps_rawlog_segment,
                       "maps per rawlog file: maps-0000.rawlog, ... (0 = one maps.rawlog, or --keep-maps maps a file "
                       "with it; config maps_rawlog_segment)")
            ->check(count);
    }
    /// As --set overrides of [pndt-map].
    void addSetsTo(std::vector<std::string>& sets) const
    {
        if (max_voxels) sets.push_back(fmt::format("pndt-map.max_voxels={}", *max_voxels));
        if (keep_maps) sets.push_back(fmt::format("pndt-map.keep_maps={}", *keep_maps));
        if (maps_rawlog_segment)
            sets.push_back(fmt::format("pndt-map.maps_rawlog_segment={}", *maps_rawlog_segment));
    }
};
}  // namespace pndt::app
