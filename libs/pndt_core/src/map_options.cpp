#include <pndt/map_options.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>
#include <algorithm>

namespace pndt
{
namespace
{
void require(bool ok, const char* field, const char* rule)
{
    if (!ok) throw std::invalid_argument(std::string("map option '") + field + "' must be " + rule);
}
bool unit(double x) { return x >= 0.0 && x <= 1.0; }
// Rules are words, not interval brackets: MRPT's config loader reads a message that ends in
// "[...]" as a source location and mangles it.
}  // namespace

void MapOptions::validate() const
{
    require(voxel_size > 0.001 && voxel_size < 10.0, "voxel_size", "above 0.001 and below 10 metres");
    require(max_range > 0 && std::isfinite(max_range), "max_range", "positive and finite");
    require(log_odds_hit > 0, "log_odds_hit", "positive");
    require(log_odds_miss < 0, "log_odds_miss", "negative");
    require(log_odds_min < 0 && log_odds_max > 0, "log_odds_min/log_odds_max", "negative / positive");
    require(ndt_min_samples >= 1, "ndt_min_samples", ">= 1");
    require(ndt_min_sigma_ratio > 0, "ndt_min_sigma_ratio", "positive");
    require(unit(miss_min_likelihood), "miss_min_likelihood", "between 0 and 1");
    require(miss_likelihood_scale > 0 && miss_likelihood_scale < 0.5, "miss_likelihood_scale", "in (0, 0.5)");
    require(sensor_sigma_base > 0, "sensor_sigma_base", "positive");
    require(sensor_sigma_quadratic >= 0, "sensor_sigma_quadratic", ">= 0");
    require(unit(theta_l), "theta_l", "between 0 and 1");
    require(unit(theta_z), "theta_z", "between 0 and 1");
    require(unit(theta_st), "theta_st", "between 0 and 1");
    require(unit(theta_b), "theta_b", "between 0 and 1");
    require(unit(theta_m), "theta_m", "between 0 and 1");
    require(unit(theta_n) && theta_n <= theta_m, "theta_n", "between 0 and theta_m");
    require(theta_o >= 0, "theta_o", ">= 0");
    require(split_coverage >= 0 && split_coverage <= 1, "split_coverage", "between 0 and 1");
    require(fragment_cover_share > 0 && fragment_cover_share < 1, "fragment_cover_share", "in (0, 1)");
    require(fragment_joint_factor >= 0 && std::isfinite(fragment_joint_factor), "fragment_joint_factor",
            ">= 0 and finite");
    require(std::isfinite(occupied_threshold) && occupied_threshold >= log_odds_min &&
                occupied_threshold < log_odds_max,
            "occupied_threshold", "at least log_odds_min and below log_odds_max");
    require(fragment_absorb_ratio >= 0 && fragment_absorb_ratio < 1, "fragment_absorb_ratio", "at least 0 and below 1");
    require(label_fill_distance >= 0 && label_fill_distance <= 100, "label_fill_distance", "between 0 and 100 m");
    require(vtou_mahalanobis_sq > 0, "vtou_mahalanobis_sq", "positive");
    require(vtou_depth_tolerance > 0, "vtou_depth_tolerance", "positive");
    require(query_mahalanobis_sq > 0, "query_mahalanobis_sq", "positive");
    require(classes.size() >= 1, "classes", "non-empty");
    require(threads >= 0 && threads <= 256, "threads", "between 0 and 256 (0 = all hardware threads)");
}

void MapOptions::applyPaperRules()
{
    ray_mode = RayMode::PerPixel;
    miss_accumulation = MissAccumulation::PerRay;
    reset_freed_voxels = false;
    instance_class_voxels = InstanceClassVoxels::TopInstance;
    semantic_eviction = false;
    void_bin = true;
    class_consistent_instances = false;
    split_coverage = 0;
    fragment_merge_frames = 0;
    fragment_absorb_ratio = 0;
    label_fill_distance = 0;
}

int MapOptions::resolvedThreads() const
{
    if (threads > 0) return threads;
    return std::max(1, std::min(256, int(std::thread::hardware_concurrency())));
}

}  // namespace pndt
