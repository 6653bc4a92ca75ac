// The [pndt-map] section: replay, poses and short-term maps.
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/poses/CPose3D.h>
#include <pndt/app/short_term_maps.h>

#include <optional>
#include <string>
#include <vector>

namespace pndt::app
{
struct MapperSettings
{
    ShortTermOptions short_term;
    std::string pose_source = "rawlog";  ///< rawlog | file
    std::string pose_file;
    std::string pose_format = "rtabmap11";
    std::string pose_frame;              ///< robot | camera; empty = the format's default
    std::string pose_label;              ///< CObservationRobotPose label; empty = any
    double pose_max_gap = 0.1;           ///< seconds
    double clock_offset = 0;             ///< seconds added to pose stamps (localiser -> camera clock)
    std::optional<mrpt::poses::CPose3D> camera_pose;  ///< robot -> camera; empty = scans' sensorPose
    std::string rgbd_label;              ///< only this range-scan sensor; empty = all
    bool maps_rawlog_inputs = false;     ///< interleave the input observations into maps.rawlog
    bool refine = false;                 ///< pose refinement (as --refine)
    std::vector<std::string> refine_options;  ///< key=value items (as --refine-option; refine_options = 'k=v k=v')

    /// Reads [pndt-map]; unknown keys and bad values are errors naming them.
    static MapperSettings load(const mrpt::config::CConfigFileBase& cfg);
};
}  // namespace pndt::app
