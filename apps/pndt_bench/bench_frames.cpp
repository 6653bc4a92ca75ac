#include "bench_frames.h"

#include <pndt/sim/renderer.h>
#include <pndt/sim/scene_builder.h>
#include <pndt/sim/trajectory.h>

#include <pndt/class_set.h>
#include <pndt/io/sequence.h>

#include <filesystem>
#include <random>
#include <stdexcept>

namespace pndt::bench
{
namespace
{
/// Coherent errors, as a network makes them: a whole segment (an instance, or
/// one class of stuff) takes a wrong class, an instance is split in two ids;
/// scores vary per pixel. `semantic` / `instance` are the clean labels.
void addNetworkLikeNoise(PanopticFrame& f, const Image<uint16_t>& semantic, const Image<uint32_t>& instance,
                         double noise, std::mt19937& rng)
{
    std::uniform_int_distribution<int> any_class(1, 40);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    const size_t width = size_t(f.K.width);
    uint16_t segment_class[64 + 41];
    bool split[64];
    for (int i = 0; i < 64 + 41; ++i) segment_class[i] = u01(rng) < noise ? uint16_t(any_class(rng)) : 0;
    for (bool& x : split) x = u01(rng) < noise;
    for (size_t i = 0; i < f.semantic.data.size(); ++i)
    {
        const uint32_t z = instance.data[i];
        const uint16_t wrong = z ? segment_class[z % 64] : segment_class[64 + semantic.data[i] % 41];
        if (wrong) f.semantic.data[i] = wrong;
        if (z && split[z % 64] && (i % width) % 64 < 32) f.instance.data[i] = z + 32;
        f.semantic_score.data[i] = 0.5f + 0.5f * u01(rng);
        f.panoptic_score.data[i] = f.semantic_score.data[i] * (0.5f + 0.5f * u01(rng));
    }
}

/// The valid depth pixels in the world, for the occupancy-only mappers.
std::vector<Eigen::Vector3f> worldPoints(const PanopticFrame& f, const Pose& T)
{
    std::vector<Eigen::Vector3f> pts;
    pts.reserve(f.depth.data.size());
    for (int row = 0; row < f.K.height; ++row)
        for (int col = 0; col < f.K.width; ++col)
            if (const float z = f.depth.at(row, col); z > 0) pts.push_back((T * f.K.unproject(col, row, z)).cast<float>());
    return pts;
}
}  // namespace

BenchFrames makeRoomFrames(int n, int width, int height, double max_range, double noise)
{
    sim::TableRoomOptions o;
    o.add_pole = true;
    const sim::Scene scene = sim::makeTableWithChairsRoom(o);
    const double s = width / 640.0;
    const CameraIntrinsics K{width, height, 525.0 * s, 525.0 * s, (width - 1) / 2.0, (height - 1) / 2.0};
    BenchFrames b;
    b.poses = sim::orbit({0, 0, 0}, 2.3, 1.5, 0.45, n);
    std::mt19937 rng(3);
    std::uniform_int_distribution<uint32_t> id(100, 1000000);
    sim::RenderedFrame r;
    for (const Pose& T : b.poses)
    {
        sim::render(scene, T, K, r, max_range);
        PanopticFrame f;
        f.K = K;
        f.depth = r.depth;
        f.semantic = r.semantic;
        f.semantic_score.resize(width, height, 0.9f);
        f.instance = r.instance;
        uint32_t perm[64];
        for (auto& p : perm) p = id(rng);
        f.panoptic_score.resize(width, height, 0.9f);
        if (noise > 0) addNetworkLikeNoise(f, r.semantic, r.instance, noise, rng);
        for (auto& z : f.instance.data) z = z ? perm[z % 64] : 0;
        b.world_points.push_back(worldPoints(f, T));
        f.scores_in_range = true;  // made in [0, 1] here, as pndt-map's decoded frames are: no check pass
        b.frames.push_back(std::move(f));
    }
    return b;
}
BenchFrames makeRecordingFrames(const std::string& folder, int n, double max_range, double noise)
{
    const io::RgbdSequence seq = io::openRecordingFolder(folder);
    std::vector<size_t> posed;
    for (size_t i = 0; i < seq.size(); ++i)
        if (seq.frames[i].T_world_cam) posed.push_back(i);
    if (posed.empty()) throw std::runtime_error(folder + ": no frame has a pose");
    const ClassSet classes = ClassSet::nyuv2_40();
    std::vector<uint16_t> things;
    for (uint16_t c = 1; c < classes.size(); ++c)
        if (classes.isThing(c)) things.push_back(c);
    const uint16_t wall = 1, floor = 2;  // NYUv2-40 stuff
    BenchFrames b;
    std::mt19937 rng(3);
    std::uniform_int_distribution<uint32_t> id(100, 1000000);
    io::FrameLoadOptions load;
    load.color = load.labels = load.predictions = false;
    // n frames spread over the recording (its whole trajectory, not its first second).
    const size_t count = std::min(posed.size(), size_t(std::max(1, n)));
    for (size_t k = 0; k < count; ++k)
    {
        const io::RgbdFrame rf = seq.load(posed[k * posed.size() / count], load);
        PanopticFrame f;
        f.K = rf.K;
        f.depth = rf.depth;
        for (float& z : f.depth.data)
            if (z > max_range) z = 0;  // as the synthetic frames: nothing beyond max range
        const int W = f.K.width, H = f.K.height;
        // Labels a network could give: a 6x6 grid of segments, the top row wall, the
        // bottom row floor, the 24 others things with a class per cell and new ids
        // every frame (the map must match them to its instances by overlap).
        Image<uint16_t> semantic(W, H);
        Image<uint32_t> instance(W, H);
        for (int r = 0; r < H; ++r)
            for (int c = 0; c < W; ++c)
            {
                const int gr = r * 6 / H, gc = c * 6 / W, cell = gr * 6 + gc;
                const bool stuff = gr == 0 || gr == 5;
                semantic.at(r, c) = gr == 0 ? wall : gr == 5 ? floor : things[size_t(cell) % things.size()];
                instance.at(r, c) = stuff ? 0 : uint32_t(cell);
            }
        f.semantic = semantic;
        f.instance = instance;
        f.semantic_score.resize(W, H, 0.9f);
        f.panoptic_score.resize(W, H, 0.9f);
        if (noise > 0) addNetworkLikeNoise(f, semantic, instance, noise, rng);
        uint32_t perm[64];
        for (auto& p : perm) p = id(rng);
        for (auto& z : f.instance.data) z = z ? perm[z % 64] : 0;
        b.poses.push_back(*rf.T_world_cam);
        b.world_points.push_back(worldPoints(f, b.poses.back()));
        f.scores_in_range = true;  // made in [0, 1] here, as pndt-map's decoded frames are: no check pass
        b.frames.push_back(std::move(f));
    }
    return b;
}
}  // namespace pndt::bench
