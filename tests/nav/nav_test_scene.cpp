// The navigation tests' scene and map (nav_test_scene.h).
#include "nav_test_scene.h"

#include <pndt/data/frame_geometry.h>
#include <pndt/data/seg_noise.h>
#include <pndt/look_at.h>
#include <pndt/mrpt/map_files.h>
#include <pndt/sim/furniture.h>
#include <pndt/sim/renderer.h>
#include <pndt/sim/scene_objects.h>
#include <pndt/sim/trajectory.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace navtest
{
using namespace pndt;

namespace
{
sim::Scene makeScene(std::vector<ObjectTruth>& truth)
{
    sim::Scene s;
    s.name = "nav_two_tables";
    s.room = Eigen::AlignedBox3d(Eigen::Vector3d(-kRoomHalfX, -kRoomHalfY, 0), Eigen::Vector3d(kRoomHalfX, kRoomHalfY, kRoomHeight));
    uint32_t id = 1;
    auto table = [&](const std::string& name, const Eigen::Vector2d& xy, double sx, double sy) {
        sim::addTable(s, {Eigen::Vector3d(xy.x(), xy.y(), 0), 0}, id++, Eigen::Vector3d(sx, sy, 0.75));
        truth.push_back({name, sim::nyu40::kTable, xy, {sx / 2, sy / 2}, 0.75});
    };
    // A chair at `xy` facing `towards` (its local +x).
    auto chair = [&](const std::string& name, const Eigen::Vector2d& xy, const Eigen::Vector2d& towards) {
        const Eigen::Vector2d d = towards - xy;
        sim::addChair(s, {Eigen::Vector3d(xy.x(), xy.y(), 0), std::atan2(d.y(), d.x())}, id++);
        truth.push_back({name, sim::nyu40::kChair, xy, {0.225, 0.225}, 0.9});
    };
    table("table A", kTableA, 1.6, 0.9);
    const Eigen::Vector2d a = kTableA;
    chair("chair A1", a + Eigen::Vector2d(-0.4, 0.80), a);
    chair("chair A2", a + Eigen::Vector2d(0.4, 0.80), a);
    chair("chair A3", a + Eigen::Vector2d(-0.4, -0.80), a);
    chair("chair A4", a + Eigen::Vector2d(0.4, -0.80), a);
    chair("chair A5", a + Eigen::Vector2d(1.15, 0), a);
    chair("chair A6", a + Eigen::Vector2d(-1.15, 0), a);
    table("table B", kTableB, 1.2, 0.8);
    const Eigen::Vector2d b = kTableB;
    chair("chair B1", b + Eigen::Vector2d(0, 0.75), b);
    chair("chair B2", b + Eigen::Vector2d(0, -0.75), b);
    chair("chair B3", b + Eigen::Vector2d(0.95, 0), b);
    sim::addTableLamp(s, {Eigen::Vector3d(b.x() - 0.3, b.y(), 0.75), 0}, id++);
    truth.push_back({"lamp on B", sim::nyu40::kLamp, b + Eigen::Vector2d(-0.3, 0), {0.1, 0.1}, 1.25});
    return s;
}

struct Data
{
    std::vector<ObjectTruth> truth;
    sim::Scene scene;
    Data() { scene = makeScene(truth); }
};
const Data& data()
{
    static const Data d;
    return d;
}
}  // namespace

const sim::Scene& scene() { return data().scene; }
const std::vector<ObjectTruth>& truth() { return data().truth; }

CameraIntrinsics camera() { return {240, 180, 120.0, 120.0, 119.5, 89.5}; }

std::vector<Pose> cameraPoses()
{
    std::vector<Pose> poses;
    // Around each table, looking down at it.
    for (const Pose& T : sim::orbit({kTableA.x(), kTableA.y(), 0}, 2.0, 1.6, 0.3, 16)) poses.push_back(T);
    for (const Pose& T : sim::orbit({kTableB.x(), kTableB.y(), 0}, 1.7, 1.6, 0.3, 14)) poses.push_back(T);
    // From the middle of the room outwards, at the walls and the floor before them.
    for (int k = 0; k < 12; ++k)
    {
        const double a = 2 * M_PI * k / 12;
        const Eigen::Vector3d eye(0.2, -0.1, 1.4);
        poses.push_back(lookAt(eye, eye + Eigen::Vector3d(3 * std::cos(a), 3 * std::sin(a), -1.3)));
    }
    return poses;
}

PanopticFrame renderFrame(const Pose& T) { return sim::renderPanopticFrame(scene(), T, camera()); }

const PanopticNDTMap& builtMap()
{
    static const PanopticNDTMap map = [] {
        PanopticNDTMap m;
        for (const Pose& T : cameraPoses()) m.integrate(renderFrame(T), T);
        m.core().finalize();
        return m;
    }();
    return map;
}

const std::string& savedMapPath()
{
    // Never destroyed, so the exit handler that removes the file can still read it.
    static const std::string* path = [] {
        const auto p = std::filesystem::temp_directory_path() / ("pndt_nav_test_" + std::to_string(::getpid()) + ".pndt.gz");
        saveArchive(builtMap(), p.string());
        auto* s = new std::string(p.string());
        std::atexit([] { std::filesystem::remove(savedMapPath()); });
        return s;
    }();
    return *path;
}

const PanopticNDTMap& loadedMap()
{
    static const PanopticNDTMap::Ptr map = loadMapArchive(savedMapPath());
    return *map;
}

PanopticFrame renderNoisyFrame(const Pose& T, uint64_t frame_index)
{
    static const data::SegmentationNoiseModel model(sim::sceneObjects(scene()), data::SegNoiseOptions{});
    PanopticFrame f = renderFrame(T);
    const data::FrameGeometry geo = data::computeFrameGeometry(f.depth, f.K, T);
    data::SegNoiseFrame n = model.apply(f.semantic, f.instance, f.depth, geo, frame_index);
    f.semantic = std::move(n.semantic);
    f.semantic_score = std::move(n.semantic_score);
    f.instance = std::move(n.instance);
    f.panoptic_score = std::move(n.panoptic_score);
    return f;
}

const PanopticNDTMap& noisyMap()
{
    static const PanopticNDTMap map = [] {
        // A longer recording than the clean map's: two laps around each table at two
        // heights and distances, as a robot would see them over a minute.
        std::vector<Pose> poses;
        for (const auto& [r, h] : {std::pair{2.0, 1.6}, std::pair{1.6, 1.1}})
        {
            for (const Pose& T : sim::orbit({kTableA.x(), kTableA.y(), 0}, r, h, 0.3, 24)) poses.push_back(T);
            for (const Pose& T : sim::orbit({kTableB.x(), kTableB.y(), 0}, r - 0.3, h, 0.3, 20, 0.3)) poses.push_back(T);
        }
        for (const Pose& T : cameraPoses()) poses.push_back(T);
        PanopticNDTMap m;
        for (size_t i = 0; i < poses.size(); ++i) m.integrate(renderNoisyFrame(poses[i], i), poses[i]);
        m.core().finalize();
        return m;
    }();
    return map;
}

const PanopticNDTMap& mapNamed(const std::string& which)
{
    return which == "loaded" ? loadedMap() : which == "noisy" ? noisyMap() : builtMap();
}

}  // namespace navtest
