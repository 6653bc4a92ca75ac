// --refine / --refine-option of pndt-map and pndt-live (issue #22): frame-to-map pose
// refinement before integration, written as refined_poses.tum.
#pragma once

#include <CLI/CLI.hpp>
#include <pndt/app/pose_refinement.h>

#include "mapper_settings.h"

#include <optional>
#include <string>
#include <vector>

namespace pndt::app
{
struct RefineCli
{
    bool enabled = false;
    std::vector<std::string> options;

    void addTo(CLI::App& app)
    {
        app.add_flag("--refine", enabled,
                     "register each frame to the current map before integrating it (NDT + Ceres, doc/refinement.md); "
                     "writes refined_poses.tum");
        app.add_option("--refine-option", options, "refinement option key=value (repeatable; implies --refine)");
    }
    /// The refinement asked for on the command line (--refine, or --refine-option) or in
    /// [pndt-map] (refine = true; refine_options alone only tune it: a config that keeps tuned
    /// options beside refine = false does not refine), if any. Command-line options are
    /// applied after the file's. Every option is checked, used or not: throws
    /// std::invalid_argument on a bad one.
    std::optional<FramePoseRefinement> make(const MapperSettings& settings) const
    {
        refine::RefineOptions ro;
        ro.enabled = true;
        for (const auto& kv : settings.refine_options) setRefineOption(ro, kv);
        for (const auto& kv : options) setRefineOption(ro, kv);
        std::optional<FramePoseRefinement> r;
        if (enabled || !options.empty() || settings.refine) r.emplace(ro);
        return r;
    }
};
}  // namespace pndt::app
