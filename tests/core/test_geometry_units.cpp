// NDT shape update, maximum-likelihood ray point, miss rule and ray walk, by hand.
#include <gtest/gtest.h>
#include <pndt/free_space.h>
#include <pndt/ray_walk.h>

#include <vector>

using namespace pndt;

TEST(NdtShape, MergesBatchesLikeOneSampleSet)
{
    NdtShape s;
    SampleBatch b;
    b.reset({0.05, 0.05, 0.05});
    b.add({0, 0, 0});
    b.add({2, 0, 0});
    s.merge(b, 0);
    EXPECT_EQ(s.n, 2u);
    EXPECT_FLOAT_EQ(s.mean[0], 1.f);
    EXPECT_NEAR(s.covariance()(0, 0), 2.0, 1e-6);  // ((1)^2 + (1)^2) / 1
    b.reset({0, 0, 0});
    b.add({4, 0, 0});
    s.merge(b, 0);
    // samples 0, 2, 4: mean 2, sample variance (4 + 0 + 4) / 2 = 4
    EXPECT_EQ(s.n, 3u);
    EXPECT_FLOAT_EQ(s.mean[0], 2.f);
    EXPECT_NEAR(s.covariance()(0, 0), 4.0, 1e-5);
    EXPECT_NEAR(s.covariance()(1, 1), 0.0, 1e-9);
}

TEST(NdtShape, CapDownWeightsOldSamples)
{
    NdtShape s;
    SampleBatch b;
    b.reset({0, 0, 0});
    for (int i = 0; i < 8; ++i) b.add({0, 0, 0});
    s.merge(b, 10);
    b.reset({0, 0, 0});
    for (int i = 0; i < 8; ++i) b.add({1, 0, 0});
    s.merge(b, 10);  // old 8 samples count as 10 - 8 = 2: mean = 8/10
    EXPECT_EQ(s.n, 10u);
    EXPECT_NEAR(s.mean[0], 0.8f, 1e-6);
}

TEST(NdtGaussian, MaximumLikelihoodPointOnALine)
{
    NdtGaussian g;
    g.mean = {2, 0, 0};
    g.cov = Eigen::Vector3d(1, 4, 1).asDiagonal();
    g.info = g.cov.inverse();
    // t = (d^T I (mu - o)) / (d^T I d) = 2 / 1.25 for d = (1,1,0)
    EXPECT_NEAR(maxLikelihoodOnLine(g, {0, 0, 0}, {1, 1, 0}), 1.6, 1e-12);
    g.cov.setIdentity();
    g.info.setIdentity();
    g.mean = {1, 0, 0};
    EXPECT_NEAR(maxLikelihoodOnLine(g, {0, 1, 0}, {1, 0, 0}), 1.0, 1e-12);
}

TEST(FreeSpace, MissThroughTheMeanFarFromTheEndpoint)
{
    NdtGaussian g;
    g.mean = {0, 0, 1};
    g.cov = Eigen::Matrix3d::Identity() * 0.01;
    g.info = g.cov.inverse();
    // Ray along z through the mean, endpoint 2 m behind it: likelihood 1.
    const double d = ndtMissDelta(g, {0, 0, 0}, {0, 0, 3}, 0.01, MissModel{});
    EXPECT_NEAR(d, -0.4054651081, 1e-9);  // log(0.4 / 0.6)
}

TEST(FreeSpace, MissOneSigmaBesideTheMean)
{
    NdtGaussian g;
    g.mean = {0.1, 0, 1};
    g.cov = Eigen::Matrix3d::Identity() * 0.01;  // sigma 0.1: ray passes at Mahalanobis 1
    g.info = g.cov.inverse();
    const double d = ndtMissDelta(g, {0, 0, 0}, {0, 0, 3}, 0.01, MissModel{});
    EXPECT_NEAR(d, -0.2438129100, 1e-9);  // p = 0.5 + 0.1 exp(-1/2)
}

TEST(FreeSpace, RaysFarFromTheGaussianOrEndingBeforeItLeaveItUntouched)
{
    NdtGaussian g;
    g.mean = {0.5, 0, 1};
    g.cov = Eigen::Matrix3d::Identity() * 0.01;  // 5 sigma away
    g.info = g.cov.inverse();
    EXPECT_EQ(ndtMissDelta(g, {0, 0, 0}, {0, 0, 3}, 0.01, MissModel{}), 0.0);
    g.mean = {0, 0, 1};
    EXPECT_EQ(ndtMissDelta(g, {0, 0, 0}, {0, 0, 0.5}, 0.01, MissModel{}), 0.0);  // ML point beyond the end
    // Endpoint right at the mean: its own measurement must not clear it.
    EXPECT_EQ(ndtMissDelta(g, {0, 0, 0}, {0, 0, 1.0}, 0.05, MissModel{}), 0.0);
}

TEST(RayWalk, VisitsEveryVoxelBeforeTheEndpointVoxel)
{
    const VoxelGrid grid(0.1);
    std::vector<VoxelKey> seen;
    walkSegment(grid, {0.05, 0.05, 0.05}, {0.35, 0.05, 0.05}, [&](const VoxelKey& k) {
        seen.push_back(k);
        return true;
    });
    ASSERT_EQ(seen.size(), 3u);
    EXPECT_EQ(seen[0], (VoxelKey{0, 0, 0}));
    EXPECT_EQ(seen[2], (VoxelKey{2, 0, 0}));

    // A diagonal in the xy-plane: one step per axis crossing, 4 + 4 steps.
    seen.clear();
    walkSegment(grid, {0.05, 0.02, 0.05}, {0.45, 0.42, 0.05}, [&](const VoxelKey& k) {
        seen.push_back(k);
        return true;
    });
    EXPECT_EQ(seen.size(), 8u);
    for (size_t i = 1; i < seen.size(); ++i)
    {
        const int manhattan = std::abs(seen[i].x - seen[i - 1].x) + std::abs(seen[i].y - seen[i - 1].y) +
                              std::abs(seen[i].z - seen[i - 1].z);
        EXPECT_EQ(manhattan, 1);
    }
    seen.clear();
    walkSegment(grid, {0.01, 0.01, 0.01}, {0.02, 0.02, 0.02}, [&](const VoxelKey& k) {
        seen.push_back(k);
        return true;
    });
    EXPECT_TRUE(seen.empty());  // same voxel: nothing before the endpoint
}

TEST(VoxelKey, PacksAndUnpacksNegativeCoordinates)
{
    const VoxelKey k{-5, 123456, -1000000};
    EXPECT_EQ(VoxelKey::unpack(k.packed()), k);
    EXPECT_TRUE(k.inRange());
    EXPECT_FALSE((VoxelKey{VoxelKey::kLimit, 0, 0}).inRange());
    const VoxelGrid grid(0.1);
    EXPECT_EQ(grid.keyOf({-0.01, 0.0, 0.19}), (VoxelKey{-1, 0, 1}));
}
