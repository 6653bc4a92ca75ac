// Every tunable of the map, with the paper's / NDT-OM's defaults.
#pragma once

#include <pndt/class_set.h>

#include <cstdint>
#include <string>

namespace pndt
{
enum class RayMode
{
    Merged,    ///< one free-space ray per distinct endpoint voxel (default, fast)
    PerPixel,  ///< one ray per valid pixel (exact, slow; for measuring the approximation)
};

struct MapOptions
{
    // --- geometry
    double voxel_size = 0.10;     ///< metres
    double max_range = 10.0;      ///< depth beyond this is skipped and counted
    bool use_ndt = true;          ///< false = the "w/o NDT" cube-voxel ablation
    RayMode ray_mode = RayMode::Merged;

    // --- occupancy (log-odds; OctoMap's defaults)
    float log_odds_hit = 0.85f;
    float log_odds_miss = -0.4f;  ///< miss for voxels without a usable Gaussian
    float log_odds_min = -2.0f;
    float log_odds_max = 3.5f;

    // --- NDT shape
    uint32_t ndt_min_samples = 3;      ///< below this a voxel has no usable Gaussian
    uint32_t ndt_sample_cap = 1000;    ///< forgetting: old samples weigh at most this many
    double ndt_min_sigma_ratio = 0.05; ///< min std-dev, as a fraction of voxel_size

    // --- NDT-aware free space (Saarinen et al., ORU NDT-OM)
    double miss_min_likelihood = 0.3;  ///< rays farther from the Gaussian leave the voxel untouched
    double miss_likelihood_scale = 0.1;///< p = 0.5 + scale * likelihood; delta = log((1-p)/p)
    double sensor_sigma_base = 0.01;   ///< endpoint noise sigma(r) = base + quad * r^2 (m)
    double sensor_sigma_quadratic = 0.0025;

    // --- semantic / instance thresholds (paper §III; ScanNet/real-world preset)
    double theta_l = 0.7;   ///< semantic score threshold
    double theta_z = 0.1;   ///< panoptic score threshold for instance updates
    double theta_st = 0.9;  ///< stuff share below which a voxel is a thing
    double theta_b = 0.8;   ///< top-z mass for back-projection
    double theta_m = 0.2;   ///< IoU above which a predicted instance is matched
    double theta_n = 0.1;   ///< IoU at or below which it gets a new id
    double theta_o = 0.25;  ///< n^Z/n^L above which a thing voxel takes its instance
    /// A predicted instance that covers at least this share of a map instance of
    /// another thing class is a merge in the segmentation (a chair with its rug):
    /// its pixels on that map instance keep the map instance's id. 0 = off (the
    /// paper's rule: the whole prediction takes one id).
    double split_coverage = 0.5;
    /// Instances keep one thing class: a prediction does not take a map instance
    /// of another class, and a voxel whose own class differs from its top
    /// instance's takes its strongest instance of its own class (top-z) if it has
    /// one. false = the paper's rules.
    bool class_consistent_instances = true;
    /// Map instances of one class that a single prediction covered (each mostly)
    /// in at least this many frames, and more than twice as often as two
    /// predictions covered them apart, are one object split early on: they are
    /// merged into the older id. 0 = off (the paper: fragments only heal through
    /// the histograms). The evidence is map state: copied and serialised with it.
    uint32_t fragment_merge_frames = 3;

    // --- finalisation (at propagation; the histograms stay as integrated)
    /// A map instance with at most this share of the voxels of a touching
    /// instance of its class is a fragment of it and joins it: the part of an
    /// object first seen apart, e.g. while the network confused its class, so no
    /// prediction ever covered both. 0 = off (the paper).
    double fragment_absorb_ratio = 0.15;
    /// Occupied voxels without semantic evidence (every view of them was below
    /// theta_L) take the most common panoptic label of their labelled
    /// 26-neighbours, growing from labelled surface up to this distance in
    /// metres. Only the panoptic output changes; 0 = off (the paper: void).
    double label_fill_distance = 0.3;

    // --- back-projection and queries
    double vtou_mahalanobis_sq = 3.0;    ///< projected-Gaussian footprint (chi^2, 2 dof)
    double vtou_depth_tolerance = 1.0;   ///< depth test, in voxel sizes
    double query_mahalanobis_sq = 9.0;   ///< render accepts a Gaussian hit within this

    ClassSet classes = ClassSet::nyuv2_40();

    // --- execution (not a property of the map: not serialised)
    /// Threads for integrate(); 0 = all hardware threads. The map is identical
    /// for every thread count (tested).
    int threads = 1;
    /// Pin integrate()'s worker threads to CPUs 1, 2, ... (the calling thread is
    /// left alone). Only for benchmarks on machines whose scheduler keeps a
    /// process's threads on one CPU; off by default.
    bool pin_threads = false;
    /// Threads integrate() will use (resolves 0).
    int resolvedThreads() const;

    /// Throws std::invalid_argument naming the first bad field.
    void validate() const;
};

}  // namespace pndt
