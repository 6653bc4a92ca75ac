// The detector front-end's geometry: CenterNet decoding, COCO → NYUv2-40 mapping, floor / wall /
// ceiling from depth planes and gravity, and box masks from depth segments, on hand-made
// tensors and analytically rendered depth images.
#include <gtest/gtest.h>
#include <pndt/seg/detector_geometry.h>

#include <cmath>
#include <limits>

using namespace pndt;
using namespace pndt::seg;

namespace
{
const ClassSet& nyu()
{
    static const ClassSet c = ClassSet::nyuv2_40();
    return c;
}
constexpr uint16_t kWall = 1, kFloor = 2, kChair = 5, kCeiling = 22;

// ---- a room rendered analytically: camera 1.5 m above the floor, looking level (optical axes:
// x right, y down, z forward) at a wall 3 m ahead; optionally a floating cube.
constexpr int W = 160, H = 120;
const CameraIntrinsics K{W, H, 100, 100, 79.5, 59.5};

struct Cube
{
    Eigen::Vector3d lo, hi;
};

/// Depth along z of the first hit of pixel (col, row): floor y = 1.5, wall z = 3, cube.
double renderDepth(int col, int row, const Cube* cube, bool* hit_cube = nullptr)
{
    const Eigen::Vector3d d((col - K.cx) / K.fx, (row - K.cy) / K.fy, 1.0);  // z = 1: t is the depth
    double t = 3.0;
    if (d.y() > 0) t = std::min(t, 1.5 / d.y());
    if (hit_cube) *hit_cube = false;
    if (cube)
    {
        double t0 = 0, t1 = 1e9;
        for (int a = 0; a < 3; ++a)
        {
            const double inv = 1.0 / d[a];
            double ta = cube->lo[a] * inv, tb = cube->hi[a] * inv;
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        if (t0 <= t1 && t0 < t)
        {
            t = t0;
            if (hit_cube) *hit_cube = true;
        }
    }
    return t;
}

Image<float> room(const Cube* cube = nullptr, Image<uint8_t>* cube_pixels = nullptr)
{
    Image<float> depth(W, H);
    if (cube_pixels) cube_pixels->resize(W, H, 0);
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
        {
            bool on_cube = false;
            depth.at(r, c) = float(renderDepth(c, r, cube, &on_cube));
            if (cube_pixels) cube_pixels->at(r, c) = on_cube ? 1 : 0;
        }
    return depth;
}

/// Where the floor meets the wall (depth 3 on the floor): ambiguous pixels, left out of checks.
bool nearFloorWallCorner(int row) { return std::abs(1.5 / ((row - K.cy) / K.fy) - 3.0) < 0.4; }
}  // namespace

// ---- CenterNet decoding --------------------------------------------------------------------

TEST(CenterNetDecode, PeaksAboveTheThresholdBecomeScaledClippedBoxesHighestFirst)
{
    // 2 classes on a 4x4 grid of a 16x16 input (stride 4), boxes scaled to a 32x32 image.
    const int G = 4;
    std::vector<float> heat(2 * G * G, 0.f), box(4 * G * G, 0.f);
    auto h = [&](int c, int y, int x) -> float& { return heat[size_t(c * G * G + y * G + x)]; };
    auto b = [&](int k, int y, int x) -> float& { return box[size_t(k * G * G + y * G + x)]; };
    h(1, 1, 2) = 0.8f;  // peak: centre (8, 4) in input pixels
    h(1, 1, 3) = 0.7f;  // beside a larger value: not a peak
    h(0, 3, 0) = 0.5f;  // peak: centre (0, 12)
    h(0, 0, 3) = 0.25f; // below the 0.3 threshold
    b(0, 1, 2) = 2, b(1, 1, 2) = 3, b(2, 1, 2) = 4, b(3, 1, 2) = 1;  // l t r b
    for (int k = 0; k < 4; ++k) b(k, 3, 0) = 8;
    CenterNetDecodeOptions o;
    o.stride = 4;
    o.score_threshold = 0.3f;
    const auto d = decodeCenterNet(heat.data(), 2, G, G, box.data(), 16, 16, 32, 32, o);
    ASSERT_EQ(d.size(), 2u);
    EXPECT_EQ(d[0].model_class, 1);
    EXPECT_FLOAT_EQ(d[0].score, 0.8f);
    // (8 - 2, 4 - 3, 8 + 4, 4 + 1) = (6, 1, 12, 5) input pixels, x2 for the image.
    EXPECT_FLOAT_EQ(d[0].x0, 12.f);
    EXPECT_FLOAT_EQ(d[0].y0, 2.f);
    EXPECT_FLOAT_EQ(d[0].x1, 24.f);
    EXPECT_FLOAT_EQ(d[0].y1, 10.f);
    // (0 - 8, 12 - 8, 0 + 8, 12 + 8) x2 = (-16, 8, 16, 40), clipped to the 32x32 image.
    EXPECT_EQ(d[1].model_class, 0);
    EXPECT_FLOAT_EQ(d[1].x0, 0.f);
    EXPECT_FLOAT_EQ(d[1].y0, 8.f);
    EXPECT_FLOAT_EQ(d[1].x1, 16.f);
    EXPECT_FLOAT_EQ(d[1].y1, 32.f);

    o.top_k = 1;
    EXPECT_EQ(decodeCenterNet(heat.data(), 2, G, G, box.data(), 16, 16, 32, 32, o).size(), 1u);
}

TEST(CenterNetDecode, APlateauGivesOneDetectionAndBadSizesAreErrors)
{
    std::vector<float> heat(9, 0.f), box(36, 1.f);
    heat[4] = heat[5] = 0.6f;  // two equal neighbours
    const auto d = decodeCenterNet(heat.data(), 1, 3, 3, box.data(), 12, 12, 12, 12, {});
    ASSERT_EQ(d.size(), 1u);
    EXPECT_FLOAT_EQ(d[0].x0, 4.f * 1 - 1.f) << "the first cell of the plateau (x = 1)";
    EXPECT_THROW(decodeCenterNet(heat.data(), 1, 0, 3, box.data(), 12, 12, 12, 12, {}), InputError);
    EXPECT_THROW(decodeCenterNet(nullptr, 1, 3, 3, box.data(), 12, 12, 12, 12, {}), InputError);
}

// ---- class mapping ---------------------------------------------------------------------------

TEST(DetectorClasses, CocoNamesMapToNyu40AndOverridesApply)
{
    const auto ids = mapDetectorClasses({"couch", "dining table", "tv", "giraffe", "chair", "book"}, {}, nyu());
    EXPECT_EQ(ids, (std::vector<uint16_t>{6, 7, 25, 40, kChair, 23}));
    EXPECT_EQ(mapDetectorClasses({"chair"}, {{"chair", ""}}, nyu()), std::vector<uint16_t>{0}) << "ignored";
    EXPECT_EQ(mapDetectorClasses({"giraffe"}, {{"giraffe", "box"}}, nyu()), std::vector<uint16_t>{29});
    EXPECT_THROW(mapDetectorClasses({"chair"}, {{"chair", "floor"}}, nyu()), InputError) << "stuff is no thing";
    EXPECT_THROW(mapDetectorClasses({"chair"}, {{"chair", "chairz"}}, nyu()), InputError);
}

// ---- planes ----------------------------------------------------------------------------------

TEST(DetectorGeometry, FloorAndWallOfARenderedRoomAreLabelledWithHighScores)
{
    const Image<float> depth = room();
    DetectorGeometryLabeller l(nyu(), {});
    PanopticFrame out;
    const auto stats = l.label(depth, K, {0, -1, 0}, {}, out);
    EXPECT_EQ(stats.planes_floor, 1);
    EXPECT_EQ(stats.planes_wall, 1);
    int checked = 0;
    for (int r = 0; r < H; ++r)
    {
        if (nearFloorWallCorner(r)) continue;
        const bool floor = r > K.cy && 1.5 / ((r - K.cy) / K.fy) < 3.0;
        for (int c = 0; c < W; ++c, ++checked)
        {
            ASSERT_EQ(out.semantic.at(r, c), floor ? kFloor : kWall) << c << "," << r;
            ASSERT_GT(out.semantic_score.at(r, c), 0.98f) << "exact planes, gravity-aligned";
            ASSERT_LE(out.semantic_score.at(r, c), 1.f);
            ASSERT_EQ(out.instance.at(r, c), 0u);
            ASSERT_EQ(out.panoptic_score.at(r, c), 0.f);
        }
    }
    EXPECT_GT(checked, W * H / 2);
}

TEST(DetectorGeometry, UpsideDownGravityMakesTheFloorACeiling)
{
    const Image<float> depth = room();
    DetectorGeometryLabeller l(nyu(), {});
    PanopticFrame out;
    const auto stats = l.label(depth, K, {0, 1, 0}, {}, out);
    EXPECT_EQ(stats.planes_ceiling, 1);
    EXPECT_EQ(stats.planes_floor, 0);
    EXPECT_EQ(out.semantic.at(H - 1, W / 2), kCeiling);
}

TEST(DetectorGeometry, InvalidDepthStaysVoidAndSizeMismatchesAreErrors)
{
    Image<float> depth = room();
    depth.at(10, 10) = 0.f;
    depth.at(10, 11) = std::numeric_limits<float>::quiet_NaN();
    DetectorGeometryLabeller l(nyu(), {});
    PanopticFrame out;
    l.label(depth, K, {0, -1, 0}, {}, out);
    EXPECT_EQ(out.semantic.at(10, 10), 0);
    EXPECT_EQ(out.semantic.at(10, 11), 0);
    EXPECT_EQ(out.semantic_score.at(10, 11), 0.f);
    EXPECT_EQ(out.semantic.at(10, 12), kWall);
    CameraIntrinsics wrong = K;
    wrong.width = 80;
    EXPECT_THROW(l.label(depth, wrong, {0, -1, 0}, {}, out), InputError);
    EXPECT_THROW(l.label(depth, K, {0, 0, 0}, {}, out), InputError);
}

// ---- box masks -------------------------------------------------------------------------------

TEST(DetectorGeometry, ABoxBecomesExactlyTheObjectInsideIt)
{
    // A cube floating in front of the wall: 0.6 m wide, 0.4 m tall, its front face 1.5 m away.
    const Cube cube{{-0.3, 0.3, 1.5}, {0.3, 0.7, 2.1}};
    Image<uint8_t> on_cube;
    const Image<float> depth = room(&cube, &on_cube);
    int x0 = W, y0 = H, x1 = 0, y1 = 0, pixels = 0;
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            if (on_cube.at(r, c))
            {
                x0 = std::min(x0, c), y0 = std::min(y0, r), x1 = std::max(x1, c + 1), y1 = std::max(y1, r + 1);
                ++pixels;
            }
    ASSERT_GT(pixels, 500);
    // The detector's box is 6 pixels larger on every side (background inside it).
    Detection d{0, 0.6f, float(x0 - 6), float(y0 - 6), float(x1 + 6), float(y1 + 6)};
    DetectorGeometryLabeller l(nyu(), {kChair});
    PanopticFrame out;
    const auto stats = l.label(depth, K, {0, -1, 0}, {d}, out);
    EXPECT_EQ(stats.detections_used, 1);
    int wrong = 0;
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
        {
            const bool in = out.instance.at(r, c) == 1;
            if (in != bool(on_cube.at(r, c))) ++wrong;
            if (!in) continue;
            EXPECT_EQ(out.semantic.at(r, c), kChair);
            EXPECT_FLOAT_EQ(out.semantic_score.at(r, c), 0.6f);
            EXPECT_FLOAT_EQ(out.panoptic_score.at(r, c), 0.36f);
        }
    EXPECT_EQ(wrong, 0) << "of " << pixels << " cube pixels";
}

TEST(DetectorGeometry, OverlappingBoxesGiveThePixelsToTheHigherScore)
{
    const Cube cube{{-0.3, 0.3, 1.5}, {0.3, 0.7, 2.1}};
    const Image<float> depth = room(&cube);
    double u0, v0, u1, v1;
    K.project({-0.3, 0.3, 1.5}, u0, v0);
    K.project({0.3, 0.7, 1.5}, u1, v1);
    const Detection low{1, 0.4f, float(u0), float(v0), float(u1), float(v1)};
    const Detection high{0, 0.7f, float(u0) - 2, float(v0) - 2, float(u1) + 2, float(v1) + 2};
    DetectorGeometryLabeller l(nyu(), {kChair, 6});
    PanopticFrame out;
    const auto stats = l.label(depth, K, {0, -1, 0}, {low, high}, out);  // given in any order
    EXPECT_EQ(stats.detections_used, 1);
    EXPECT_EQ(stats.detections_dropped, 1);
    EXPECT_EQ(out.instance.at(int((v0 + v1) / 2), int((u0 + u1) / 2)), 1u) << "ids in score order";
    EXPECT_EQ(out.semantic.at(int((v0 + v1) / 2), int((u0 + u1) / 2)), kChair);
}

TEST(DetectorGeometry, IgnoredClassesAndEmptyBoxesAreDropped)
{
    const Image<float> depth = room();
    DetectorGeometryLabeller l(nyu(), {0});
    PanopticFrame out;
    const auto stats = l.label(depth, K, {0, -1, 0}, {Detection{0, 0.9f, 10, 10, 40, 40}}, out);
    EXPECT_EQ(stats.detections_used, 0);
    EXPECT_EQ(stats.detections_dropped, 1);
    for (uint32_t z : out.instance.data) ASSERT_EQ(z, 0u);
}
