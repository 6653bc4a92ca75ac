#include "mapper_settings.h"

#include <fmt/format.h>
#include <mrpt/core/bits_math.h>
#include <pndt/app/pose_refinement.h>
#include <pndt/mrpt/config_section.h>

#include <cmath>
#include <sstream>

namespace pndt::app
{
MapperSettings MapperSettings::load(const mrpt::config::CConfigFileBase& cfg)
{
    MapperSettings s;
    ConfigSection c(cfg, "pndt-map");
    std::string unit = "seconds", camera;
    c.read("period", s.short_term.period);
    c.read("period_unit", unit);
    c.read("warmup", s.short_term.warmup);
    c.read("stable_ids", s.short_term.stable_ids);
    c.read("write_ply", s.short_term.write_ply);
    c.read("map_prefix", s.short_term.prefix);
    c.read("max_voxels", s.short_term.max_voxels);
    c.read("keep_maps", s.short_term.keep_maps);
    c.read("pose_source", s.pose_source);
    c.read("pose_file", s.pose_file);
    c.read("pose_format", s.pose_format);
    c.read("pose_frame", s.pose_frame);
    c.read("pose_label", s.pose_label);
    c.read("pose_max_gap", s.pose_max_gap);
    c.read("clock_offset", s.clock_offset);
    c.read("camera_pose", camera);
    c.read("rgbd_label", s.rgbd_label);
    c.read("maps_rawlog", s.short_term.write_rawlog);
    c.read("maps_rawlog_label", s.short_term.rawlog_label);
    c.read("maps_rawlog_inputs", s.maps_rawlog_inputs);
    c.read("maps_rawlog_segment", s.short_term.rawlog_segment_maps);
    std::string refine_options;
    c.read("refine", s.refine);
    c.read("refine_options", refine_options);
    c.rejectUnknownKeys();
    const auto bad = [](const std::string& key, const std::string& v, const char* what) {
        return std::invalid_argument(fmt::format("config [pndt-map] key '{}': '{}' {}", key, v, what));
    };
    if (unit == "frames")
        s.short_term.period_in_frames = true;
    else if (unit != "seconds")
        throw bad("period_unit", unit, "is not seconds or frames");
    if (s.short_term.period < 0) throw bad("period", std::to_string(s.short_term.period), "must be >= 0");
    if (s.short_term.warmup < 0 || s.short_term.warmup >= 1)
        throw bad("warmup", std::to_string(s.short_term.warmup), "must be in [0, 1)");
    if (s.pose_source != "rawlog" && s.pose_source != "file") throw bad("pose_source", s.pose_source, "is not rawlog or file");
    if (s.pose_source == "file" && s.pose_file.empty()) throw bad("pose_file", "", "is required with pose_source=file");
    if (!(s.pose_max_gap > 0)) throw bad("pose_max_gap", std::to_string(s.pose_max_gap), "must be positive");
    if (!std::isfinite(s.clock_offset)) throw bad("clock_offset", std::to_string(s.clock_offset), "must be finite");
    {
        std::istringstream in(refine_options);
        refine::RefineOptions check;
        for (std::string kv; in >> kv;)
        {
            try
            {
                setRefineOption(check, kv);
            }
            catch (const std::invalid_argument& e)
            {
                throw bad("refine_options", kv, e.what());
            }
            s.refine_options.push_back(kv);
        }
    }
    if (!camera.empty())
    {
        std::istringstream in(camera);
        double x, y, z, yaw, pitch, roll;
        std::string rest;
        if (!(in >> x >> y >> z >> yaw >> pitch >> roll) || (in >> rest))
            throw bad("camera_pose", camera, "is not 'x y z yaw pitch roll' (metres, degrees)");
        s.camera_pose = mrpt::poses::CPose3D(x, y, z, mrpt::DEG2RAD(yaw), mrpt::DEG2RAD(pitch), mrpt::DEG2RAD(roll));
    }
    return s;
}
}  // namespace pndt::app
