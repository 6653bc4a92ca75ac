// vtou by hand: a known Gaussian's ellipse and a cube's box in a 20x20 image,
// and the depth test.
#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "mask_footprint.h"

using namespace pndt;

namespace
{
const CameraIntrinsics kK{20, 20, 100.0, 100.0, 9.5, 9.5};

/// Every (row, column) of the footprint, row by row.
std::set<std::pair<int, int>> pixelsOf(const MaskFootprint& fp, double k2)
{
    std::set<std::pair<int, int>> out;
    for (int r = fp.r0; r <= fp.r1; ++r)
    {
        int c0, c1;
        if (!footprintRow(fp, r, k2, c0, c1)) continue;
        for (int c = c0; c <= c1; ++c) out.emplace(r, c);
    }
    return out;
}
}  // namespace

TEST(MaskFootprint, AGaussianTwoMetresAheadCoversThePixelCentresOfItsEllipse)
{
    // Mean on the optical axis at 2 m: J = diag(fx/z, fy/z) = 50 px/m; sigma_x =
    // sigma_y = 2 cm -> 1 px in u and v. At Mahalanobis^2 4 (2 sigma): columns
    // and rows 9.5 +- 2, i.e. 8..11; a row dv = 1.5 from the centre keeps
    // |du| <= sqrt(4 - 2.25) = 1.32 (columns 9, 10), a row dv = 0.5 |du| <= 1.94
    // (columns 8..11): 12 pixels, a plus sign.
    NdtGaussian g;
    g.mean = {0, 0, 2};
    g.cov = Eigen::Vector3d(4e-4, 4e-4, 1e-6).asDiagonal();
    g.info = g.cov.inverse();
    const MaskFootprint fp = gaussianFootprint(g, Pose::Identity(), kK, 4.0);
    ASSERT_TRUE(fp.ellipse);
    EXPECT_DOUBLE_EQ(fp.u0, 9.5);
    EXPECT_DOUBLE_EQ(fp.v0, 9.5);
    EXPECT_DOUBLE_EQ(fp.z0, 2.0);
    EXPECT_EQ(fp.c0, 8);
    EXPECT_EQ(fp.c1, 11);
    EXPECT_EQ(fp.r0, 8);
    EXPECT_EQ(fp.r1, 11);
    const std::set<std::pair<int, int>> expected = {{8, 9},  {8, 10},  {9, 8},   {9, 9},   {9, 10},  {9, 11},
                                                    {10, 8}, {10, 9},  {10, 10}, {10, 11}, {11, 9},  {11, 10}};
    EXPECT_EQ(pixelsOf(fp, 4.0), expected);

    // Seen from a camera 1 m further back (the world moves +1 m in z): half the size.
    Pose back = Pose::Identity();
    back.translation() = Eigen::Vector3d(0, 0, 1);
    const MaskFootprint far = gaussianFootprint(g, back, kK, 4.0);
    EXPECT_DOUBLE_EQ(far.z0, 3.0);
    // sigma 2/3 px: |du| <= 1.33 on the centre rows -> columns 9, 10 in rows 9..10 only
    // (rows 8 and 11 are 1.5 px = 2.25 sigma away).
    EXPECT_EQ(pixelsOf(far, 4.0), (std::set<std::pair<int, int>>{{9, 9}, {9, 10}, {10, 9}, {10, 10}}));

    // Behind the camera: nothing.
    g.mean = {0, 0, -1};
    EXPECT_TRUE(pixelsOf(gaussianFootprint(g, Pose::Identity(), kK, 4.0), 4.0).empty());
}

TEST(MaskFootprint, ACubeCoversThePixelCentresOfItsProjectedBox)
{
    // The voxel [0, 0.1] x [0, 0.1] x [2.0, 2.1]: u from 9.5 (x = 0) to 9.5 + 100 *
    // 0.1 / 2.0 = 14.5 (near face), so pixel centres 10..14 (9 and 15 lie outside);
    // the same in v. Depth of its centre 2.05.
    const MaskFootprint fp = cubeFootprint({0, 0, 2.0}, 0.1, Pose::Identity(), kK);
    EXPECT_FALSE(fp.ellipse);
    EXPECT_EQ(fp.c0, 10);
    EXPECT_EQ(fp.c1, 14);
    EXPECT_EQ(fp.r0, 10);
    EXPECT_EQ(fp.r1, 14);
    EXPECT_DOUBLE_EQ(fp.z0, 2.05);
    EXPECT_EQ(pixelsOf(fp, 4.0).size(), 25u);
    // Clipped at the image border: a cube reaching past column 19.
    const MaskFootprint edge = cubeFootprint({0.15, 0, 2.0}, 0.1, Pose::Identity(), kK);
    EXPECT_EQ(edge.c0, 17);  // 9.5 + 100 * 0.15 / 2.1 = 16.64
    EXPECT_EQ(edge.c1, 19);
}

TEST(MaskFootprint, TheDepthTestKeepsPixelsWithinOneToleranceOfTheVoxel)
{
    MaskFootprint fp;
    fp.z0 = 2.05;
    EXPECT_TRUE(agreesInDepth(fp, 2.05f, 0.1));
    EXPECT_TRUE(agreesInDepth(fp, 2.14f, 0.1));
    EXPECT_FALSE(agreesInDepth(fp, 2.16f, 0.1));   // behind the voxel: a wall it hides
    EXPECT_FALSE(agreesInDepth(fp, 1.90f, 0.1));   // in front: something occludes it
    EXPECT_FALSE(agreesInDepth(fp, std::numeric_limits<float>::quiet_NaN(), 0.1));
}
