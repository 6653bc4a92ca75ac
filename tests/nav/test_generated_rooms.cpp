// "The table with the most chairs" on pndt-generate's procedural rooms (pndt_sim's
// indoor scenes: dining, office, hall), walked through with a hand-held camera and
// mapped from ground-truth labels, checked against the scene's own furniture.
#include <gtest/gtest.h>
#include <pndt/mrpt/PanopticNDTMap.h>
#include <pndt/nav/object_query.h>
#include <pndt/sim/indoor_scene.h>
#include <pndt/sim/renderer.h>
#include <pndt/sim/scene_objects.h>
#include <pndt/sim/walk_trajectory.h>

using namespace pndt;
using namespace pndt::nav;

namespace
{
constexpr int kChair = 5, kTable = 7;

/// Ground truth: chairs per table, each chair for the nearest table within 0.6 m (footprints as AABBs).
std::map<uint32_t, int> truthChairsAround(const std::vector<sim::SceneObject>& objs)
{
    auto gap = [](const sim::SceneObject& a, const sim::SceneObject& b) {
        const Eigen::Vector2d d = (a.bounds.min().head<2>() - b.bounds.max().head<2>())
                                      .cwiseMax(b.bounds.min().head<2>() - a.bounds.max().head<2>())
                                      .cwiseMax(0.0);
        return d.norm();
    };
    std::map<uint32_t, int> out;
    for (const auto& t : objs)
        if (t.semantic == kTable) out[t.instance] = 0;
    for (const auto& c : objs)
    {
        if (c.semantic != kChair) continue;
        const sim::SceneObject* best = nullptr;
        for (const auto& t : objs)
            if (t.semantic == kTable && gap(c, t) <= 0.6 && (!best || gap(c, t) < gap(c, *best))) best = &t;
        if (best) ++out[best->instance];
    }
    return out;
}

class GeneratedRooms : public ::testing::TestWithParam<std::string>
{
};
}  // namespace

TEST_P(GeneratedRooms, TheTableWithTheMostChairsIsTheTrueOne)
{
    const sim::Scene scene = sim::makeIndoorScene(sim::indoorScenePreset(GetParam()));
    const auto truth_objects = sim::sceneObjects(scene);
    const auto truth = truthChairsAround(truth_objects);
    if (truth.empty()) GTEST_SKIP() << GetParam() << " has no table";
    // Two laps of a hand-held walk at 320 x 240.
    sim::WalkOptions w;
    w.n_frames = 120;
    w.laps = 2;
    const CameraIntrinsics K{320, 240, 288.9, 288.9, 159.5, 119.5};
    PanopticNDTMap map;
    for (const Pose& T : sim::walkTrajectory(scene, w))
    {
        map.integrate(sim::renderPanopticFrame(scene, T, K), T);
    }
    const auto objs = mapObjects(map.core(), GetParam(), 5);
    const QueryResult q = runQuery(objs, map.core().options().classes, "the table with the most chairs");
    std::string truth_text;
    int most = -1, tables_with_most = 0;
    uint32_t best_truth = 0;
    for (const auto& [id, n] : truth)
    {
        truth_text += " " + std::to_string(n);
        if (n > most) most = n, tables_with_most = 0, best_truth = id;
        if (n == most) ++tables_with_most;
    }
    std::cout << "  " << GetParam() << ": truth chairs per table" << truth_text << "; map: " << q.summary << "\n";
    ASSERT_TRUE(q.best());
    EXPECT_EQ(int(q.matches[0].related.size()), most);
    if (tables_with_most == 1)
    {
        const auto& t = *std::find_if(truth_objects.begin(), truth_objects.end(),
                                      [&](const sim::SceneObject& o) { return o.instance == best_truth; });
        EXPECT_LT((q.best()->centroid.head<2>() - t.center().head<2>()).norm(), 0.3);
    }
}

INSTANTIATE_TEST_SUITE_P(Presets, GeneratedRooms, ::testing::Values("dining", "office", "hall"));
