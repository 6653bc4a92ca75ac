// Every tunable of the map, with the paper's / NDT-OM's defaults.
#pragma once

#include <pndt/class_set.h>
#include <pndt/types.h>

#include <cstdint>
#include <string>

namespace pndt
{
enum class RayMode
{
    Merged,    ///< one free-space ray per distinct endpoint voxel (default, fast)
    PerPixel,  ///< one ray per valid pixel (exact, slow; for measuring the approximation)
};

/// How the free-space rays of one frame lower a voxel's log-odds.
enum class MissAccumulation
{
    Strongest,  ///< one miss per voxel per frame: the strongest of the rays that crossed it (default, fast)
    PerRay,     ///< every ray that crosses a voxel applies its miss (NDT-OM's per-ray form, the paper)
};

/// Which voxels' semantic histograms decide a map instance's class (paper Eq. 9).
enum class InstanceClassVoxels
{
    /// Only voxels that take the instance in propagation (pthing and top-z):
    /// a voxel that saw the instance too rarely to carry it (n^Z/n^L < theta_o)
    /// does not vote for its class either (default, ours: such voxels are mostly
    /// the border of a neighbouring object, and their class is the neighbour's).
    PanopticThing,
    /// Every voxel whose top h^Z entry is the instance (Eq. 9 as the paper states it).
    TopInstance,
};

struct MapOptions
{
    // --- geometry
    double voxel_size = 0.10;     ///< metres
    double max_range = 10.0;      ///< metres; pixels beyond are skipped and counted
    /// What max_range limits: the depth z (default, the paper's) or the length of the
    /// pixel's ray (a sensor's range spec); at the image corners of a 640x480 Kinect
    /// the ray is 1.12 z.
    RangeKind max_range_along = RangeKind::Z;
    bool use_ndt = true;          ///< false = the "w/o NDT" cube-voxel ablation
    RayMode ray_mode = RayMode::Merged;

    // --- occupancy (log-odds; OctoMap's defaults)
    float log_odds_hit = 0.85f;
    float log_odds_miss = -0.4f;  ///< miss for voxels without a usable Gaussian
    float log_odds_min = -2.0f;
    float log_odds_max = 3.5f;
    /// A voxel is occupied when its log-odds are above this (0 = p > 0.5).
    float occupied_threshold = 0.0f;
    MissAccumulation miss_accumulation = MissAccumulation::Strongest;
    /// A voxel whose log-odds drop below the occupied threshold loses its
    /// NDT shape and histograms (a moved chair leaves nothing behind). false = it
    /// keeps them and only its occupancy changes (the paper says nothing of
    /// wiping, so its preset keeps them).
    bool reset_freed_voxels = true;

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
    double theta_o = 0.25;  ///< n^Z/n^L at or above which a thing voxel takes its instance
    /// Which voxels vote for a map instance's class (Eq. 9); see InstanceClassVoxels.
    InstanceClassVoxels instance_class_voxels = InstanceClassVoxels::PanopticThing;
    /// h^L keeps at most LabelRecord::kSemanticCapacity (8) classes in the voxel
    /// record; when full, a new class replaces the weakest (true, default: a
    /// surface voxel rarely sees more than 3-4 classes). false = no eviction:
    /// classes beyond the record go to a per-map overflow store, so h^L holds
    /// every class it was given (the paper's dense histogram).
    bool semantic_eviction = true;
    /// Void pixels (class 0) with S^L > theta_l add to a void bin of h^L (true:
    /// the paper's 41-bin histogram over NYUv2-40 + void; void counts as stuff
    /// and a voxel whose argmax is void reads as void). false (default): void
    /// means "no prediction" and leaves h^L alone; the pixel still maps geometry.
    bool void_bin = false;
    /// A predicted instance that covers at least this share of a map instance of
    /// another thing class is a merge in the segmentation (a chair with its rug):
    /// its pixels on that map instance keep the map instance's id. 0 = off (the
    /// paper's rule: the whole prediction takes one id). 0.7: chosen on the
    /// validation scenes.
    double split_coverage = 0.7;
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
    /// 8: chosen on the validation scenes (doc/results.md, "Validation").
    uint32_t fragment_merge_frames = 8;
    /// Fragment evidence: masks smaller than this (pixels) say too little to count.
    uint32_t fragment_min_mask_pixels = 50;
    /// Fragment evidence: a prediction "covers" a map instance when it holds more
    /// than this share of the instance's mask.
    double fragment_cover_share = 0.5;
    /// Fragment evidence: merge when joint frames exceed this many times the apart ones.
    double fragment_joint_factor = 2.0;

    // --- finalisation (at propagation; the histograms stay as integrated)
    /// A map instance with at most this share of the voxels of a touching
    /// instance of its class is a fragment of it and joins it: the part of an
    /// object first seen apart, e.g. while the network confused its class, so no
    /// prediction ever covered both. 0 = off (the paper). 0.35: chosen on the
    /// validation scenes, the top of the range tried (beyond 1 : 3, two touching
    /// objects of one class are no longer rare).
    double fragment_absorb_ratio = 0.35;
    /// Occupied voxels without semantic evidence (every view of them was below
    /// theta_L) take the most common panoptic label of their labelled
    /// 26-neighbours, growing from labelled surface up to this distance in
    /// metres. Only the panoptic output changes; 0 = off (the paper: void).
    /// 0.2 m: chosen on the validation scenes.
    double label_fill_distance = 0.2;

    // --- back-projection and queries
    double vtou_mahalanobis_sq = 3.0;    ///< projected-Gaussian footprint (chi^2, 2 dof)
    double vtou_depth_tolerance = 1.0;   ///< depth test, in voxel sizes
    double query_mahalanobis_sq = 9.0;   ///< render accepts a Gaussian hit within this

    ClassSet classes = ClassSet::nyuv2_40();

    // --- execution (not a property of the map: not serialised)
    /// Threads for integrate(); 0 = all hardware threads. The map is identical
    /// for every thread count (tested). More threads than CPUs only cost: their
    /// idle threads then sleep instead of spinning between stages (WorkerPool::spins).
    int threads = 1;
    /// Pin integrate()'s worker threads to CPUs 1, 2, ... (the calling thread is
    /// left alone). Only for benchmarks on machines whose scheduler keeps a
    /// process's threads on one CPU; off by default.
    bool pin_threads = false;
    /// Threads integrate() will use (resolves 0).
    int resolvedThreads() const;

    /// Throws std::invalid_argument naming the first bad field.
    void validate() const;

    /// Every rule as the paper states it (arXiv v2, Eq. 2-10), none of ours:
    /// per-pixel rays applying per-ray misses, no wiping, Eq. 9 over every top
    /// voxel, a dense h^L with a void bin, the five rules beyond the paper off.
    /// Geometry, thresholds and execution options are left as they are. The
    /// same as config/presets/paper.ini (tested).
    void applyPaperRules();
};

}  // namespace pndt
