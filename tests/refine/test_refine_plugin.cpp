// The plugin's insertion option refine_pose: frames go through the pose refiner before they
// are integrated; a wall straight ahead is refused (degenerate) and integrated unrefined.
#include <gtest/gtest.h>
#include <pndt/mrpt/PanopticNDTMap.h>
#include <pndt/refine/pose_refiner.h>

TEST(RefinePlugin, InsertionOptionRunsTheRefiner)
{
    pndt::PanopticNDTMap map;
    EXPECT_FALSE(map.insertionOptions.refine_pose);
    map.insertionOptions.refine_pose = true;
    pndt::PanopticFrame f;
    f.K.width = 80;
    f.K.height = 60;
    f.K.fx = f.K.fy = 60;
    f.K.cx = 39.5;
    f.K.cy = 29.5;
    f.depth = pndt::Image<float>(80, 60, 2.0f);  // a wall 2 m ahead
    for (int i = 0; i < 4; ++i)
    {
        pndt::Pose T = pndt::Pose::Identity();
        T.translation().x() = 0.01 * i;
        map.integrate(f, T);
    }
    ASSERT_NE(map.refiner(), nullptr);
    const auto& st = map.refiner()->stats();
    EXPECT_EQ(st.frames, 4u);
    EXPECT_EQ(st.accepted(), 0u);  // the first frame meets an empty map, a single plane never pins 6 DoF
    EXPECT_EQ(st.fallbacks(), 4u);
    EXPECT_FALSE(map.isEmpty());

    // The in-place path (a range scan's uint16 image) is refined too.
    pndt::PanopticNDTMap view_map;
    view_map.insertionOptions.refine_pose = true;
    const std::vector<uint16_t> mm(80 * 60, 2000);
    pndt::FrameView v;
    v.K = f.K;
    v.depth = pndt::DepthView::units(mm.data(), 80, 60, 0.001);
    for (int i = 0; i < 3; ++i) view_map.integrate(v, pndt::Pose::Identity());
    ASSERT_NE(view_map.refiner(), nullptr);
    EXPECT_EQ(view_map.refiner()->stats().frames, 3u);
    EXPECT_EQ(view_map.refiner()->stats().fallbacks(), 3u);
}

// clear() kept the refiner and its carried correction: the cleared map's next frame was moved
// by a correction estimated against voxels no longer there. A copy starts its own refiner too.
TEST(RefinePlugin, ClearAndCopiesStartWithoutACarriedCorrection)
{
    pndt::PanopticNDTMap map;
    map.insertionOptions.refine_pose = true;
    pndt::PanopticFrame f;
    f.K = {80, 60, 60, 60, 39.5, 29.5};
    f.depth = pndt::Image<float>(80, 60, 2.0f);
    map.integrate(f, pndt::Pose::Identity());
    ASSERT_NE(map.refiner(), nullptr);
    pndt::PanopticNDTMap copy(map);
    EXPECT_EQ(copy.refiner(), nullptr);
    pndt::PanopticNDTMap assigned;
    assigned.insertionOptions.refine_pose = true;
    assigned.integrate(f, pndt::Pose::Identity());
    assigned = map;
    EXPECT_EQ(assigned.refiner(), nullptr);
    map.clear();
    EXPECT_TRUE(map.isEmpty());
    EXPECT_EQ(map.refiner(), nullptr);
    map.integrate(f, pndt::Pose::Identity());
    ASSERT_NE(map.refiner(), nullptr);
    EXPECT_EQ(map.refiner()->stats().frames, 1u);  // a new refiner: the frame before clear() is gone
}
