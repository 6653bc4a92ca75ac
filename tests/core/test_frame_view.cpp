// FrameView: a camera's uint16 units, strided rows and ray-length depth map
// exactly like the float metres along z they stand for; max_range along rays.
#include <gtest/gtest.h>
#include <pndt/panoptic_map.h>
#include <pndt/sim/renderer.h>
#include <pndt/sim/scene_builder.h>
#include <pndt/sim/trajectory.h>

#include <cmath>
#include <cstring>

using namespace pndt;

namespace
{
const CameraIntrinsics kK{160, 120, 131.25, 131.25, 79.5, 59.5};

struct Frames
{
    std::vector<Pose> poses;
    std::vector<std::vector<uint16_t>> millimetres;
    std::vector<PanopticFrame> frames;  ///< depth = the millimetres as float metres
};

Frames makeFrames()
{
    Frames d;
    const sim::Scene scene = sim::makeTableWithChairsRoom();
    d.poses = sim::orbit({0, 0, 0}, 2.2, 1.4, 0.5, 5);
    sim::RenderedFrame r;
    for (const Pose& T : d.poses)
    {
        sim::render(scene, T, kK, r, 8.0);
        std::vector<uint16_t> mm(r.depth.data.size());
        PanopticFrame f;
        f.K = kK;
        f.depth.resize(kK.width, kK.height);
        for (size_t i = 0; i < mm.size(); ++i)
        {
            const float z = r.depth.data[i];
            mm[i] = z > 0 && z < 65.f ? uint16_t(std::lround(z * 1000.f)) : 0;
            f.depth.data[i] = float(mm[i]) * float(0.001);  // what the view path computes
        }
        f.semantic = r.semantic;
        f.semantic_score.resize(kK.width, kK.height, 0.9f);
        f.instance = r.instance;
        f.panoptic_score.resize(kK.width, kK.height, 0.8f);
        d.millimetres.push_back(std::move(mm));
        d.frames.push_back(std::move(f));
    }
    return d;
}

void expectSameMap(const PanopticMap& x, const PanopticMap& y)
{
    ASSERT_EQ(x.voxels().size(), y.voxels().size());
    EXPECT_EQ(x.voxels().packedKeys(), y.voxels().packedKeys());
    EXPECT_EQ(0, std::memcmp(x.voxels().voxels().data(), y.voxels().voxels().data(), sizeof(Voxel) * x.voxels().size()));
    ASSERT_EQ(x.surfaceRecords().size(), y.surfaceRecords().size());
    EXPECT_EQ(0, std::memcmp(x.surfaceRecords().data(), y.surfaceRecords().data(),
                             sizeof(SurfaceRecord) * x.surfaceRecords().size()));
    const auto ia = x.instances(), ib = y.instances();
    ASSERT_EQ(ia.size(), ib.size());
    for (size_t i = 0; i < ia.size(); ++i)
    {
        EXPECT_EQ(ia[i].id, ib[i].id);
        EXPECT_EQ(ia[i].semantic, ib[i].semantic);
        EXPECT_EQ(ia[i].voxel_count, ib[i].voxel_count);
    }
}

/// `src` copied into rows `stride` elements apart (the padding holds garbage).
template <typename T>
std::vector<T> padded(const std::vector<T>& src, int width, int height, size_t stride, T garbage)
{
    std::vector<T> out(stride * size_t(height), garbage);
    for (int r = 0; r < height; ++r) std::memcpy(&out[size_t(r) * stride], &src[size_t(r) * width], sizeof(T) * width);
    return out;
}
}  // namespace

TEST(FrameView, Uint16MillimetresMapLikeFloatMetres)
{
    const Frames d = makeFrames();
    MapOptions o;
    o.voxel_size = 0.05;
    PanopticMap a(o), b(o);
    uint64_t over_a = 0, over_b = 0;
    for (size_t i = 0; i < d.frames.size(); ++i)
    {
        over_a += a.integrate(d.frames[i], d.poses[i]).valid_pixels;
        FrameView v(d.frames[i]);
        v.depth = DepthView::units(d.millimetres[i].data(), kK.width, kK.height, 0.001);
        over_b += b.integrate(v, d.poses[i]).valid_pixels;
    }
    EXPECT_GT(over_a, 10000u);
    EXPECT_EQ(over_a, over_b);
    expectSameMap(a, b);
}

TEST(FrameView, StridedRowsMapLikeContiguousOnes)
{
    const Frames d = makeFrames();
    MapOptions o;
    PanopticMap a(o), b(o);
    const size_t stride = size_t(kK.width) + 7;
    for (size_t i = 0; i < d.frames.size(); ++i)
    {
        const PanopticFrame& f = d.frames[i];
        a.integrate(f, d.poses[i]);
        // Garbage in the padding: an out-of-range class there would throw if read.
        const auto depth = padded(f.depth.data, kK.width, kK.height, stride, 1.5f);
        const auto sem = padded(f.semantic.data, kK.width, kK.height, stride, uint16_t(9999));
        const auto sem_score = padded(f.semantic_score.data, kK.width, kK.height, stride, 7.f);
        const auto inst = padded(f.instance.data, kK.width, kK.height, stride, 12345u);
        const auto pan_score = padded(f.panoptic_score.data, kK.width, kK.height, stride, 7.f);
        FrameView v;
        v.K = kK;
        v.depth = DepthView::metres(depth.data(), kK.width, kK.height, stride);
        v.semantic = {sem.data(), kK.width, kK.height, stride};
        v.semantic_score = {sem_score.data(), kK.width, kK.height, stride};
        v.instance = {inst.data(), kK.width, kK.height, stride};
        v.panoptic_score = {pan_score.data(), kK.width, kK.height, stride};
        b.integrate(v, d.poses[i]);
    }
    expectSameMap(a, b);
}

TEST(FrameView, RayLengthDepthIsConvertedToZ)
{
    // A wall 2.05 m in front of the camera: its ray lengths grow towards the
    // corners; given as ray lengths, it must land in the same voxels as z.
    const CameraIntrinsics K{64, 48, 32, 32, 31.5, 23.5};
    PanopticFrame z_frame;
    z_frame.K = K;
    z_frame.depth.resize(K.width, K.height, 2.05f);
    std::vector<float> ray(size_t(K.width) * K.height);
    for (int r = 0; r < K.height; ++r)
        for (int c = 0; c < K.width; ++c)
        {
            const double x = (c - K.cx) / K.fx, y = (r - K.cy) / K.fy;
            ray[size_t(r) * K.width + c] = float(2.05 * std::sqrt(1 + x * x + y * y));
        }
    // Corner pixel (0, 0): x = -0.984, y = -0.734, ray = 2.05 * 1.5837 = 3.247 m.
    EXPECT_NEAR(ray[0], 3.2466, 1e-3);
    MapOptions o;
    o.voxel_size = 0.1;
    PanopticMap a(o), b(o);
    a.integrate(z_frame, Pose::Identity());
    FrameView v;
    v.K = K;
    v.depth = DepthView::metres(ray.data(), K.width, K.height, 0, RangeKind::Ray);
    b.integrate(v, Pose::Identity());
    EXPECT_EQ(a.voxels().packedKeys(), b.voxels().packedKeys());
    EXPECT_EQ(a.occupiedCount(), b.occupiedCount());
    EXPECT_GT(a.occupiedCount(), 50u);
}

TEST(FrameView, MaxRangeAlongRaysSkipsTheFarCornersOfAWall)
{
    // Wall at z = 2.05 m, max_range 2.5 m: along z every pixel is in range; along
    // rays, pixels with sqrt(1 + x² + y²) > 2.5 / 2.05 = 1.2195 are beyond it.
    const CameraIntrinsics K{64, 48, 32, 32, 31.5, 23.5};
    PanopticFrame f;
    f.K = K;
    f.depth.resize(K.width, K.height, 2.05f);
    uint64_t beyond = 0;
    for (int r = 0; r < K.height; ++r)
        for (int c = 0; c < K.width; ++c)
        {
            const double x = (c - K.cx) / K.fx, y = (r - K.cy) / K.fy;
            beyond += x * x + y * y > (2.5 / 2.05) * (2.5 / 2.05) - 1;
        }
    // x² + y² > 0.4872: the pixels outside an ellipse of radii 22.3 x 22.3 px.
    EXPECT_GT(beyond, 1000u);
    EXPECT_LT(beyond, 2000u);
    MapOptions o;
    o.max_range = 2.5;
    PanopticMap along_z(o);
    EXPECT_EQ(along_z.integrate(f, Pose::Identity()).skipped_over_range, 0u);
    o.max_range_along = RangeKind::Ray;
    PanopticMap along_ray(o);
    const FrameStats st = along_ray.integrate(f, Pose::Identity());
    EXPECT_EQ(st.skipped_over_range, beyond);
    EXPECT_EQ(st.valid_pixels, uint64_t(K.width) * K.height - beyond);
}

TEST(FrameView, BadViewsAreRefusedNamingTheSource)
{
    const CameraIntrinsics K{8, 6, 10, 10, 3.5, 2.5};
    std::vector<uint16_t> mm(48, 1000);
    FrameView v;
    v.K = K;
    v.source = "camera 'xtion' @ 12.5";
    PanopticMap map{MapOptions{}};
    const auto message = [&] {
        try
        {
            map.integrate(v, Pose::Identity());
        }
        catch (const InputError& e)
        {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(message(), "camera 'xtion' @ 12.5: depth image is 0x0 (no pixels) but the intrinsics are for 8x6");
    v.depth = DepthView::units(mm.data(), 8, 6, 0.0);
    EXPECT_EQ(message(), "camera 'xtion' @ 12.5: depth scale 0 metres per unit is not positive");
    v.depth = DepthView::units(mm.data(), 8, 6, 0.001, 4);
    EXPECT_EQ(message(), "camera 'xtion' @ 12.5: depth row stride 4 is less than the width 8");
    v.depth = DepthView::units(mm.data(), 8, 6, 0.001);
    std::vector<uint16_t> sem(40, 1);
    v.semantic = {sem.data(), 8, 5};
    EXPECT_EQ(message(), "camera 'xtion' @ 12.5: semantic image is 8x5 but the depth image is 8x6");
    v.semantic = {};
    EXPECT_EQ(message(), "no error");
    EXPECT_GT(map.voxels().size(), 0u);
}

// Intrinsics and poses an integrator can get wrong: each refused by name, by integrate() and by
// render() alike (render() walked endless rays for fx = 0 or 1e-12).
TEST(FrameView, BadIntrinsicsAndPosesAreNamedByIntegrateAndRender)
{
    const CameraIntrinsics good{8, 6, 10, 10, 3.5, 2.5};
    EXPECT_EQ(good.invalidReason(), "");
    auto with = [&](auto change) {
        CameraIntrinsics K = good;
        change(K);
        return K;
    };
    const std::vector<std::pair<CameraIntrinsics, std::string>> bad = {
        {with([](CameraIntrinsics& K) { K.width = -5; }), "size -5x6 is not positive"},
        {with([](CameraIntrinsics& K) { K.fx = 0; }), "fx=0.000000 is not a positive number"},
        {with([](CameraIntrinsics& K) { K.fy = NAN; }), "fy=nan is not a positive number"},
        {with([](CameraIntrinsics& K) { K.cx = NAN; }), "cx=nan is not a number"},
        {with([](CameraIntrinsics& K) { K.cy = INFINITY; }), "cy=inf is not a number"},
        // The edge columns are 3.5 from cx: fx must be at least 0.035 (tan 89.4 degrees = 100).
        {with([](CameraIntrinsics& K) { K.fx = 0.034; }), "more than 89.4 degrees off the optical axis"},
    };
    EXPECT_EQ(with([](CameraIntrinsics& K) { K.fx = 0.036; }).invalidReason(), "");
    std::vector<uint16_t> mm(48, 1000);
    PanopticMap map{MapOptions{}};
    FrameView v;
    v.depth = DepthView::units(mm.data(), 8, 6, 0.001);
    v.source = "cam";
    v.K = good;
    map.integrate(v, Pose::Identity());
    RenderedView out;
    for (const auto& [K, what] : bad)
    {
        EXPECT_NE(K.invalidReason().find(what), std::string::npos) << K.invalidReason();
        v.K = K;
        try
        {
            map.integrate(v, Pose::Identity());
            ADD_FAILURE() << "integrate took " << what;
        }
        catch (const InputError& e)
        {
            EXPECT_EQ(std::string(e.what()).rfind("cam: invalid camera intrinsics: ", 0), 0u) << e.what();
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
        try
        {
            map.render(Pose::Identity(), K, out);
            ADD_FAILURE() << "render took " << what;
        }
        catch (const InputError& e)
        {
            EXPECT_EQ(std::string(e.what()).rfind("render: invalid camera intrinsics: ", 0), 0u) << e.what();
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    }
    // A rotation matrix from the unnormalised quaternion (0.6, 0.6, 0, 0): a rotation scaled by 0.72.
    Pose scaled = Pose::Identity();
    scaled.linear() = Eigen::Quaterniond(0.6, 0.6, 0, 0).toRotationMatrix();  // not normalised
    EXPECT_NE(poseInvalidReason(scaled).find("not a rotation"), std::string::npos) << poseInvalidReason(scaled);
    EXPECT_EQ(poseInvalidReason(Pose(Eigen::Quaterniond(0.6, 0.6, 0, 0).normalized())), "");
    v.K = good;
    EXPECT_THROW(map.integrate(v, scaled), InputError);
    EXPECT_THROW(map.render(scaled, good, out), InputError);
    Pose nan_pose = Pose::Identity();
    nan_pose.translation().x() = NAN;
    EXPECT_THROW(map.render(nan_pose, good, out), InputError);
}

// Scores are probabilities: one frame's 5.0 ("sure") outvoted four frames of 0.9 for another
// class. Refused by name unless the frame says its scores are fractions by construction.
TEST(FrameView, ScoresOutsideZeroToOneAreRefusedByPixel)
{
    const CameraIntrinsics K{8, 6, 10, 10, 3.5, 2.5};
    std::vector<uint16_t> mm(48, 1000), sem(48, 5);
    std::vector<float> score(48, 0.9f);
    FrameView v;
    v.K = K;
    v.source = "net";
    v.depth = DepthView::units(mm.data(), 8, 6, 0.001);
    v.semantic = {sem.data(), 8, 6};
    v.semantic_score = {score.data(), 8, 6};
    PanopticMap map{MapOptions{}};
    map.integrate(v, Pose::Identity());
    for (const float bad : {5.0f, -0.1f, float(NAN)})
    {
        score[13] = bad;  // row 1, col 5
        try
        {
            map.integrate(v, Pose::Identity());
            ADD_FAILURE() << bad << " taken";
        }
        catch (const InputError& e)
        {
            EXPECT_NE(std::string(e.what()).find("net: semantic score"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("at pixel (row 1, col 5) is not a probability (0 to 1)"),
                      std::string::npos)
                << e.what();
        }
    }
    score[13] = 1.0f;
    EXPECT_NO_THROW(map.integrate(v, Pose::Identity()));
    score[13] = 5.0f;
    v.scores_in_range = true;  // the caller vouches for them: no check pass
    EXPECT_NO_THROW(map.integrate(v, Pose::Identity()));
}
