// The presets in config/presets, loaded as pndt-map loads them (defaults, then
// the preset): "paper" must be the paper's rules, every one of them.
#include <gtest/gtest.h>
#include <pndt/app/layered_config.h>
#include <pndt/mrpt/PanopticNDTMap.h>

#include <sstream>

using namespace pndt;

namespace
{
MapOptions presetOptions(const std::string& preset)
{
    const std::string dir = PNDT_CONFIG_DIR;
    const auto cfg = app::loadLayeredConfig({dir + "/panoptic_ndt.ini", dir + "/presets/" + preset + ".ini"}, {});
    MapOptions o;
    loadMapOptions(cfg, "MAP_PanopticNDTMap_00_creationOpts", o);
    return o;
}
}  // namespace

TEST(Presets, PaperIsEveryRuleOfThePaper)
{
    const MapOptions o = presetOptions("paper");
    // The five rules beyond the paper, off.
    EXPECT_FALSE(o.class_consistent_instances);
    EXPECT_EQ(o.split_coverage, 0.0);
    EXPECT_EQ(o.fragment_merge_frames, 0u);
    EXPECT_EQ(o.fragment_absorb_ratio, 0.0);
    EXPECT_EQ(o.label_fill_distance, 0.0);
    // Eq. 9 over every voxel whose top h^Z entry is the instance.
    EXPECT_EQ(o.instance_class_voxels, InstanceClassVoxels::TopInstance);
    // h^L dense over the class set (nothing evicted), void one of its bins.
    EXPECT_FALSE(o.semantic_eviction);
    EXPECT_TRUE(o.void_bin);
    // Nothing wiped when a voxel turns free.
    EXPECT_FALSE(o.reset_freed_voxels);
    // NDT-OM free space: a ray per pixel, each applying its miss.
    EXPECT_EQ(o.ray_mode, RayMode::PerPixel);
    EXPECT_EQ(o.miss_accumulation, MissAccumulation::PerRay);
    EXPECT_TRUE(o.use_ndt);
    // The paper's thresholds (ScanNet preset).
    EXPECT_EQ(o.theta_l, 0.7);
    EXPECT_EQ(o.theta_z, 0.1);
    EXPECT_EQ(o.theta_st, 0.9);
    EXPECT_EQ(o.theta_b, 0.8);
    EXPECT_EQ(o.theta_m, 0.2);
    EXPECT_EQ(o.theta_n, 0.1);
    EXPECT_EQ(o.theta_o, 0.25);
}

TEST(Presets, PaperFixesEveryOptionANewOneMustBeDecidedHere)
{
    // Every map option as the paper preset leaves it. A new option changes this
    // text: decide its paper value (in config/presets/paper.ini) and update it.
    std::ostringstream dump;
    dumpMapOptions(presetOptions("paper"), dump);
    EXPECT_EQ(dump.str(),
              "voxel_size = 0.1\nmax_range = 10\nmax_range_along = z\nuse_ndt = true\nray_mode = per_pixel\nmiss_accumulation = per_ray\n"
              "log_odds_hit = 0.85\nlog_odds_miss = -0.4\nlog_odds_min = -2\nlog_odds_max = 3.5\n"
              "occupied_threshold = 0\nreset_freed_voxels = false\nndt_min_samples = 3\nndt_sample_cap = 1000\n"
              "ndt_min_sigma_ratio = 0.05\nmiss_min_likelihood = 0.3\nmiss_likelihood_scale = 0.1\n"
              "sensor_sigma_base = 0.01\nsensor_sigma_quadratic = 0.0025\n"
              "theta_l = 0.7\ntheta_z = 0.1\ntheta_st = 0.9\ntheta_b = 0.8\ntheta_m = 0.2\ntheta_n = 0.1\n"
              "theta_o = 0.25\ninstance_class_voxels = top_instance\nsemantic_eviction = false\nvoid_bin = true\n"
              "split_coverage = 0\nclass_consistent_instances = false\nfragment_merge_frames = 0\n"
              "fragment_min_mask_pixels = 50\nfragment_cover_share = 0.5\nfragment_joint_factor = 2\n"
              "fragment_absorb_ratio = 0\nlabel_fill_distance = 0\nvtou_mahalanobis_sq = 3\n"
              "vtou_depth_tolerance = 1\nquery_mahalanobis_sq = 9\nthreads = 1\nclasses = 41\n");
}

TEST(Presets, PaperFileEqualsTheCoreRulesTheExperimentsUse)
{
    MapOptions rules;
    rules.applyPaperRules();
    std::ostringstream file, core;
    dumpMapOptions(presetOptions("paper"), file);
    dumpMapOptions(rules, core);
    EXPECT_EQ(file.str(), core.str());
}

TEST(Presets, RealWorldUsesTheAppendixMatchingThresholds)
{
    const MapOptions o = presetOptions("realworld");
    EXPECT_EQ(o.theta_m, 0.3);
    EXPECT_EQ(o.theta_n, 0.2);
    EXPECT_EQ(o.theta_l, 0.7);
    EXPECT_EQ(o.theta_z, 0.1);
    EXPECT_EQ(o.max_range, 5.0);
    // Our rules stay on in the real-world preset.
    EXPECT_TRUE(o.class_consistent_instances);
}

TEST(Presets, DetectorThresholdsAcceptEveryLabelTheDetectorFrontEndGives)
{
    // The front-end keeps detections scoring > 0.3: S^L = score, S^P = score^2.
    const MapOptions o = presetOptions("detector");
    EXPECT_LT(o.theta_l, 0.3);
    EXPECT_LT(o.theta_z, 0.3 * 0.3);
    EXPECT_GT(o.theta_l, 0.2) << "a plane fit below half quality is still rejected (stuff S^L >= 0.5 a)";
}

TEST(Presets, AnUnknownKeyInAPresetIsAnErrorNamingIt)
{
    const std::string dir = PNDT_CONFIG_DIR;
    auto cfg = app::loadLayeredConfig({dir + "/panoptic_ndt.ini"}, {"MAP_PanopticNDTMap_00_creationOpts.miss_acumulation=per_ray"});
    MapOptions o;
    try
    {
        loadMapOptions(cfg, "MAP_PanopticNDTMap_00_creationOpts", o);
        FAIL() << "expected an error";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("miss_acumulation"), std::string::npos) << e.what();
    }
    cfg = app::loadLayeredConfig({dir + "/panoptic_ndt.ini"}, {"MAP_PanopticNDTMap_00_creationOpts.miss_accumulation=sometimes"});
    try
    {
        loadMapOptions(cfg, "MAP_PanopticNDTMap_00_creationOpts", o);
        FAIL() << "expected an error";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("'sometimes' is not one of strongest, per_ray"), std::string::npos)
            << e.what();
    }
    // max_range along rays, and a wrong value named with the choices.
    cfg = app::loadLayeredConfig({dir + "/panoptic_ndt.ini"}, {"MAP_PanopticNDTMap_00_creationOpts.max_range_along=ray"});
    loadMapOptions(cfg, "MAP_PanopticNDTMap_00_creationOpts", o);
    EXPECT_EQ(o.max_range_along, RangeKind::Ray);
    cfg = app::loadLayeredConfig({dir + "/panoptic_ndt.ini"}, {"MAP_PanopticNDTMap_00_creationOpts.max_range_along=euclid"});
    try
    {
        loadMapOptions(cfg, "MAP_PanopticNDTMap_00_creationOpts", o);
        FAIL() << "expected an error";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("'euclid' is not one of z, ray"), std::string::npos) << e.what();
    }
}
