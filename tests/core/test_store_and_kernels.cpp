// The brick voxel store, the worker pool and the hot-path kernels, each against
// a plain reference: find/create/assign round trips, every SIMD projection
// kernel against the scalar one, the fast miss rule against ndtMissDelta, the
// integer sample sums against double sums, and the histogram runs against one
// SparseHistogram::add per pixel.
#include <gtest/gtest.h>
#include <pndt/free_space.h>
#include <pndt/panoptic_map.h>
#include <pndt/record_pool.h>

#include <atomic>
#include <ctime>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <thread>
#include <cstdio>

#include <sys/resource.h>
#include <unistd.h>

#include "predicted_pixels.h"
#include "projection_kernels.h"
#include "worker_pool.h"

using namespace pndt;

namespace
{
struct Record44  // the size of a SurfaceRecord: not a divisor of the page size
{
    uint32_t v[11];
};
long minorFaults()
{
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_minflt;
}
}  // namespace

TEST(RecordPool, GrowsByRemappingKeepingEveryRecordAndTouchingEachPageOnce)
{
    const size_t page = size_t(sysconf(_SC_PAGESIZE));
    RecordPool<Record44> pool;
    EXPECT_EQ(pool.bytesUsed(), 0u);
    const size_t n = 1'500'000;  // 66 MB, many remaps
    const long faults0 = minorFaults();
    for (uint32_t i = 0; i < n; ++i)
    {
        Record44& r = pool.emplace_back();
        EXPECT_EQ(r.v[0] | r.v[10], 0u);  // value-initialised
        for (uint32_t k = 0; k < 11; ++k) r.v[k] = i * 11 + k;
    }
    const long faults = minorFaults() - faults0;
    size_t wrong = 0;
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t k = 0; k < 11; ++k) wrong += pool[i].v[k] != i * 11 + k;
    EXPECT_EQ(wrong, 0u);
    // A copying pool would first-touch its final size about twice (doubling)
    // or five times (growth by a quarter); this one once.
    const size_t pages = (n * sizeof(Record44) + page - 1) / page;
    EXPECT_LE(size_t(faults), pages + pages / 5) << "minor page faults while growing";
    EXPECT_EQ(pool.bytesUsed(), pages * page);
    EXPECT_GE(pool.capacity(), n);

    RecordPool<Record44> copy = pool;
    ASSERT_EQ(copy.size(), n);
    EXPECT_EQ(0, std::memcmp(copy.data(), pool.data(), n * sizeof(Record44)));
    RecordPool<Record44> moved = std::move(pool);
    EXPECT_EQ(moved.size(), n);
    EXPECT_EQ(pool.size(), 0u);
    EXPECT_EQ(pool.bytesUsed(), 0u);
    moved.clear();
    EXPECT_EQ(moved.capacity(), 0u);
    EXPECT_EQ(moved.bytesUsed(), 0u);
}

TEST(RecordPool, ResizeAssignAndPushBackLikeAVector)
{
    RecordPool<uint32_t> p;
    p.resize(5, 7u);
    p.push_back(9);
    const std::vector<uint32_t> want{7, 7, 7, 7, 7, 9};
    EXPECT_EQ(std::vector<uint32_t>(p.begin(), p.end()), want);
    p.resize(2);
    EXPECT_EQ(p.size(), 2u);
    EXPECT_EQ(p.back(), 7u);
    const std::vector<uint32_t> src{1, 2, 3};
    p.assign(src.begin(), src.end());
    EXPECT_EQ(std::vector<uint32_t>(p.begin(), p.end()), src);
    p.assign(src.end(), src.end());
    EXPECT_TRUE(p.empty());
}

TEST(VoxelStoreBricks, FindCreateAcrossBrickBoundariesAndNegativeCoordinates)
{
    VoxelStore store;
    std::vector<VoxelKey> order;
    for (int z = -10; z < 10; ++z)
        for (int x = 9; x >= -10; --x)  // not in memory order on purpose
            for (int y = -10; y < 10; y += 3) order.push_back({x, y, z});
    for (size_t i = 0; i < order.size(); ++i) EXPECT_EQ(store.findOrCreate(order[i]), uint32_t(i));
    ASSERT_EQ(store.size(), order.size());
    for (size_t i = 0; i < order.size(); ++i)
    {
        EXPECT_EQ(store.find(order[i]), uint32_t(i));
        EXPECT_EQ(store.key(uint32_t(i)), order[i]);
        EXPECT_EQ(store.findOrCreate(order[i]), uint32_t(i));  // no second voxel
    }
    EXPECT_EQ(store.size(), order.size());
    // x, z in -10..9 span bricks -2..1; y in {-10,..,8} spans bricks -2..1: 4^3 bricks.
    EXPECT_EQ(store.brickCount(), 64u);
    EXPECT_EQ(store.find({0, -9, 0}), kNoRecord);       // in a brick, never created
    EXPECT_EQ(store.find({100, 100, 100}), kNoRecord);  // no brick at all
    const auto keys = store.packedKeys();
    for (size_t i = 0; i < order.size(); ++i) EXPECT_EQ(keys[i], order[i].packed());
    // Brick coordinates floor towards minus infinity.
    EXPECT_EQ(VoxelStore::brickKeyOf({-1, -8, -9}), (VoxelKey{-1, -1, -2}.packed()));
    EXPECT_EQ(VoxelStore::slotOf({-1, -8, -9}), 7u | (0u << 3) | (7u << 6));
}

TEST(VoxelStoreBricks, GridLimitsAreStorable)
{
    VoxelStore store;
    const int32_t m = VoxelKey::kLimit - 1;
    const std::vector<VoxelKey> corners = {{m, m, m}, {-m, -m, -m}, {m, -m, 0}, {0, 0, 0}};
    for (const VoxelKey& k : corners) store.findOrCreate(k);
    for (size_t i = 0; i < corners.size(); ++i)
    {
        EXPECT_EQ(store.find(corners[i]), uint32_t(i));
        EXPECT_EQ(store.key(uint32_t(i)), corners[i]);
    }
}

TEST(VoxelStoreBricks, AssignRoundTripRebuildsTheSameStore)
{
    VoxelStore a;
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> d(-40, 40);
    for (int i = 0; i < 3000; ++i)
    {
        const uint32_t vi = a.findOrCreate({d(rng), d(rng), d(rng) / 4});
        a[vi].occ = float(i) * 0.25f - 100.f;
        a[vi].surface = i % 3 ? kNoRecord : uint32_t(i);
    }
    VoxelStore b;
    b.assign(a.packedKeys(), {a.voxels().begin(), a.voxels().end()});
    ASSERT_EQ(b.size(), a.size());
    EXPECT_EQ(b.brickCount(), a.brickCount());
    EXPECT_EQ(b.packedKeys(), a.packedKeys());
    EXPECT_EQ(0, std::memcmp(a.voxels().data(), b.voxels().data(), a.size() * sizeof(Voxel)));
    for (uint32_t i = 0; i < a.size(); ++i) EXPECT_EQ(b.find(a.key(i)), i);
    // New voxels continue the same way in both.
    EXPECT_EQ(a.findOrCreate({1000, 0, 0}), b.findOrCreate({1000, 0, 0}));
}

TEST(VoxelStoreBricks, AssignRejectsBadInput)
{
    VoxelStore s;
    const uint64_t k = VoxelKey{1, 2, 3}.packed();
    EXPECT_THROW(s.assign({k, k}, std::vector<Voxel>(2)), std::invalid_argument);  // duplicate
    EXPECT_THROW(s.assign({k}, std::vector<Voxel>(2)), std::invalid_argument);     // size mismatch
    EXPECT_THROW(s.assign({~uint64_t(0)}, std::vector<Voxel>(1)), std::invalid_argument);  // not a key
    EXPECT_THROW(s.assign({0}, std::vector<Voxel>(1)), std::invalid_argument);  // -kLimit: off the grid
}

TEST(WorkerPool, RunsEveryTaskOnceOnAnyThreadAndRethrows)
{
    for (int threads : {1, 2, 5})
    {
        WorkerPool pool(threads);
        std::vector<std::atomic<int>> seen(1000);
        std::atomic<int> bad_thread{0};
        pool.runWithThread(1000, [&](int task, int thread) {
            seen[size_t(task)].fetch_add(1);
            if (thread < 0 || thread >= threads) bad_thread.fetch_add(1);
        });
        for (auto& s : seen) EXPECT_EQ(s.load(), 1);
        EXPECT_EQ(bad_thread.load(), 0);
        EXPECT_THROW(pool.run(10, [](int task) {
            if (task == 7) throw std::runtime_error("task 7");
        }),
                     std::runtime_error);
        std::atomic<int> after{0};
        pool.run(3, [&](int) { after.fetch_add(1); });  // the pool still works
        EXPECT_EQ(after.load(), 3);
    }
}

TEST(WorkerPool, ThreadsBeyondTheCpusSleepInsteadOfSpinning)
{
    // 64 threads on 2 CPUs mapped 10-13x slower than one: idle workers spun up to 20 ms
    // between stages on the CPUs the working threads needed.
    const int cpus = int(std::thread::hardware_concurrency());
    if (cpus == 0) GTEST_SKIP() << "CPU count unknown";
    EXPECT_TRUE(WorkerPool(cpus).spins());
    WorkerPool pool(cpus + 2);
    EXPECT_FALSE(pool.spins());
    // Idle within a burst (between a frame's stages): the workers' CPU time stays near zero
    // (spinning, each would burn up to 20 ms of it).
    const WorkerPool::Burst burst(&pool);
    std::atomic<int> done{0};
    pool.run(64, [&](int) { done.fetch_add(1); });
    const std::clock_t before = std::clock();
    std::this_thread::sleep_for(std::chrono::milliseconds(40));
    const double cpu_ms = 1000.0 * double(std::clock() - before) / CLOCKS_PER_SEC;
    EXPECT_LT(cpu_ms, 10.0) << (cpus + 1) << " idle workers";
    EXPECT_EQ(done.load(), 64);
    // Every task still runs once, background pieces too.
    std::vector<std::atomic<int>> seen(500);
    pool.run(500, [&](int t) { seen[size_t(t)].fetch_add(1); });
    for (auto& s : seen) EXPECT_EQ(s.load(), 1);
    std::atomic<int> pieces{0};
    auto piece = [&](int) { return pieces.fetch_add(1) < 99; };
    {
        WorkerPool::Background bg(&pool, piece);
        bg.finish();
    }
    EXPECT_GE(pieces.load(), 100);
}

TEST(WorkerPool, CountsTheWorkersBusyTimeAndTheCallersWait)
{
    using std::chrono::milliseconds;
    WorkerPool one(1);
    one.run(4, [](int) { std::this_thread::sleep_for(milliseconds(2)); });
    EXPECT_EQ(one.workersBusy().count(), 0);  // the caller ran them: no worker, no wait
    EXPECT_EQ(one.callerWaiting().count(), 0);

    // Two tasks, two threads: each task waits for the other thread to hold the
    // other task, so the worker runs one. Its task then takes 40 ms more, which
    // the caller, done at once, waits out.
    WorkerPool two(2);
    std::atomic<int> arrived{0};
    std::atomic<int> worker_tasks{0};
    two.runWithThread(2, [&](int, int thread) {
        arrived.fetch_add(1);
        const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (arrived.load() < 2 && std::chrono::steady_clock::now() < give_up) std::this_thread::yield();
        if (thread != 0)
        {
            worker_tasks.fetch_add(1);
            std::this_thread::sleep_for(milliseconds(40));
        }
    });
    ASSERT_EQ(worker_tasks.load(), 1);
    EXPECT_GE(two.workersBusy(), milliseconds(40));
    // About the worker's 40 ms, less the time the caller took to see the other arrive.
    EXPECT_GE(two.callerWaiting(), milliseconds(20));
    EXPECT_LE(two.callerWaiting(), two.workersBusy() + milliseconds(1000));
}

TEST(WorkerPool, BackgroundPiecesRunOnceBesideTheCallersTasksAndRethrow)
{
    for (int threads : {1, 2, 3})
    {
        WorkerPool pool(threads);
        const WorkerPool::Burst burst(&pool);
        constexpr int kPieces = 2000;
        std::vector<std::atomic<int>> piece_seen(kPieces);
        std::atomic<int> next{0}, bad_thread{0};
        auto piece = [&](int thread) {
            const int i = next.fetch_add(1);
            if (i >= kPieces) return false;
            if (thread < 0 || thread >= threads) bad_thread.fetch_add(1);
            piece_seen[size_t(i)].fetch_add(1);
            return true;
        };
        {
            WorkerPool::Background bg(&pool, piece);
            // The caller's own stages meanwhile: every task still runs once.
            for (int round = 0; round < 20; ++round)
            {
                std::vector<std::atomic<int>> task_seen(64);
                pool.runWithThread(64, [&](int task, int thread) {
                    task_seen[size_t(task)].fetch_add(1);
                    if (thread < 0 || thread >= threads) bad_thread.fetch_add(1);
                });
                for (auto& t : task_seen) ASSERT_EQ(t.load(), 1);
            }
            bg.finish();
            // finish() returns with every piece done and no worker inside one.
            for (auto& p : piece_seen) ASSERT_EQ(p.load(), 1);
        }
        EXPECT_EQ(bad_thread.load(), 0);

        // A piece's exception reaches finish(); the pool works on.
        std::atomic<int> left{50};
        auto failing = [&](int) {
            const int i = left.fetch_sub(1);
            if (i == 20) throw std::runtime_error("piece 20");
            return i > 1;
        };
        WorkerPool::Background bad(&pool, failing);
        EXPECT_THROW(bad.finish(), std::runtime_error);
        EXPECT_LE(left.load(), 20);  // the throwing piece ran
        std::atomic<int> after{0};
        pool.run(3, [&](int) { after.fetch_add(1); });
        EXPECT_EQ(after.load(), 3);
    }
}

namespace
{
/// A projection of a random camera; `far` puts it near the grid's edge so that
/// some pixels fall off the grid.
ProjectionSetup randomSetup(std::mt19937& rng, int W, int H, bool far)
{
    std::uniform_real_distribution<double> u(-1, 1);
    const Eigen::Quaterniond q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
    Pose T = Pose::Identity();
    T.linear() = q.toRotationMatrix();
    const double vs = 0.05;
    T.translation() = far ? Eigen::Vector3d((VoxelKey::kLimit - 30) * vs, u(rng), -(VoxelKey::kLimit - 20) * vs)
                          : Eigen::Vector3d(u(rng) * 3, u(rng) * 3, u(rng));
    ProjectionSetup P;
    const double scale = kSampleScale / vs;
    const Eigen::Matrix3d R = T.linear() * scale;
    const Eigen::Vector3d t = (T.translation() / vs + Eigen::Vector3d::Constant(VoxelKey::kLimit)) * kSampleScale;
    for (int i = 0; i < 3; ++i)
    {
        P.t[i] = t[i];
        P.col[i].resize(size_t(W));
        for (int c = 0; c < W; ++c) P.col[i][size_t(c)] = R(i, 0) * ((c - W / 2.0) / 300.0);
    }
    P.row.resize(3 * size_t(H));
    for (int r = 0; r < H; ++r)
        for (int i = 0; i < 3; ++i) P.row[3 * size_t(r) + i] = R(i, 1) * ((r - H / 2.0) / 300.0) + R(i, 2);
    P.max_range = 8.0;
    P.inside = !far;
    return P;
}
}  // namespace

TEST(ProjectionKernels, EverySimdVersionGivesTheScalarBits)
{
    std::mt19937 rng(11);
    const int W = 203, H = 7;  // odd width: the vector loops leave a scalar tail
    std::uniform_real_distribution<float> depth(0.05f, 9.f);
    std::uniform_int_distribution<int> special(0, 12);
    std::vector<ProjectRowFn> kernels = {&projectRowSse2};
    if (ProjectRowFn avx2 = projectRowAvx2()) kernels.push_back(avx2);
    if (ProjectRowFn avx512 = projectRowAvx512()) kernels.push_back(avx512);
    size_t outside = 0, checked = 0;
    for (int trial = 0; trial < 40; ++trial)
    {
        const ProjectionSetup P = randomSetup(rng, W, H, trial % 4 == 3);
        std::vector<float> row(static_cast<size_t>(W), 0.f);
        for (int r = 0; r < H; ++r)
        {
            for (float& z : row)
            {
                const int what = special(rng);
                if (what == 0)
                    z = 0.f;
                else if (what == 1)
                    z = -1.f;
                else if (what == 2)
                    z = std::numeric_limits<float>::quiet_NaN();
                else if (what == 3)
                    z = std::numeric_limits<float>::infinity();
                else if (what == 4)
                    z = 8.5f;  // beyond max_range
                else
                    z = depth(rng);
            }
            RowBuffer ref, got;
            ref.resize(W);
            got.resize(W);
            projectRowScalar(P, &P.row[3 * size_t(r)], row.data(), 0, W, ref);
            for (ProjectRowFn k : kernels)
            {
                k(P, &P.row[3 * size_t(r)], row.data(), 0, W, got);
                for (int c = 0; c < W; ++c)
                {
                    ASSERT_EQ(got.key[size_t(c)], ref.key[size_t(c)]) << "trial " << trial << " col " << c;
                    if (ref.key[size_t(c)] >= kFirstSpecialKey) continue;
                    for (int i = 0; i < 3; ++i)
                        ASSERT_EQ(std::memcmp(&got.q[i][size_t(c)], &ref.q[i][size_t(c)], sizeof(double)), 0);
                    ++checked;
                }
            }
            for (uint64_t k : ref.key) outside += k == kOutsideKey;
        }
    }
    EXPECT_GT(outside, 0u);
    EXPECT_GT(checked, 10000u);
}

TEST(ProjectionKernels, TheGridsEdgesAreTheScalarOnesInEveryVersion)
{
    // G = t exactly (zero ray directions, depth 1): grid coordinates at the ends
    // of the grid, 2^20 (the first field) and (2^21) 2^20 (one past the last),
    // and their neighbouring doubles. The SIMD versions compare G with the ends
    // instead of G / 2^20 with 1 and 2^21: this pins that down bit for bit.
    const double lo = kSampleScale, hi = double(1 << 21) * kSampleScale;
    const double edges[] = {std::nextafter(lo, 0.0), lo, std::nextafter(lo, 2 * lo), std::nextafter(hi, 0.0), hi,
                            std::nextafter(hi, 2 * hi)};
    const bool in_grid[] = {false, true, true, true, false, false};
    const int W = 19;  // a full step of each vector width and a scalar tail
    std::vector<ProjectRowFn> kernels = {&projectRowSse2};
    if (ProjectRowFn avx2 = projectRowAvx2()) kernels.push_back(avx2);
    if (ProjectRowFn avx512 = projectRowAvx512()) kernels.push_back(avx512);
    for (int axis = 0; axis < 3; ++axis)
        for (size_t e = 0; e < std::size(edges); ++e)
        {
            ProjectionSetup P;
            for (int i = 0; i < 3; ++i)
            {
                P.t[i] = i == axis ? edges[e] : 1000.5 * kSampleScale;
                P.col[i].assign(size_t(W), 0.0);
            }
            P.row.assign(3, 0.0);
            P.max_range = 8.0;
            const std::vector<float> depth(size_t(W), 1.f);
            RowBuffer ref, got;
            ref.resize(W);
            got.resize(W);
            projectRowScalar(P, P.row.data(), depth.data(), 0, W, ref);
            EXPECT_EQ(ref.key[0] != kOutsideKey, in_grid[e]) << "axis " << axis << " edge " << e;
            for (ProjectRowFn k : kernels)
            {
                k(P, P.row.data(), depth.data(), 0, W, got);
                for (int c = 0; c < W; ++c)
                {
                    ASSERT_EQ(got.key[size_t(c)], ref.key[size_t(c)]) << "axis " << axis << " edge " << e << " col " << c;
                    if (ref.key[size_t(c)] >= kFirstSpecialKey) continue;
                    for (int i = 0; i < 3; ++i)
                        ASSERT_EQ(std::memcmp(&got.q[i][size_t(c)], &ref.q[i][size_t(c)], sizeof(double)), 0);
                }
            }
        }
}

TEST(ProjectionKernels, KeysAreTheVoxelsOfThePoints)
{
    // The scalar kernel's key is floor of the grid coordinate: check against
    // VoxelGrid::keyOf on points well inside their voxels.
    std::mt19937 rng(3);
    const ProjectionSetup P = randomSetup(rng, 64, 4, false);
    std::vector<float> row(64, 2.5f);
    RowBuffer out;
    out.resize(64);
    projectRowScalar(P, &P.row[0], row.data(), 0, 64, out);
    for (int c = 0; c < 64; ++c)
    {
        const VoxelKey k = VoxelKey::unpack(out.key[size_t(c)]);
        // Grid coordinate back from G: key + (q + half + 0.5) / 2^18.
        for (int i = 0; i < 3; ++i)
        {
            const double G = P.t[i] + 2.5 * (P.row[size_t(i)] + P.col[i][size_t(c)]);
            const double g = G / kSampleScale - VoxelKey::kLimit;
            const int32_t ki = i == 0 ? k.x : i == 1 ? k.y : k.z;
            EXPECT_EQ(ki, int32_t(std::floor(g)));
            EXPECT_NEAR(out.q[i][size_t(c)], std::floor((g - std::floor(g)) * kSampleScale) - kSampleHalf, 1.0);
        }
    }
}

TEST(FastMissRule, EqualsNdtMissDeltaToTheBit)
{
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> u(-1, 1);
    for (const double min_lik : {0.0, 0.3, 0.9, 1.0})
    {
        const MissModel model{min_lik, 0.1};
        const FastMissRule rule(model);
        int nonzero = 0;
        for (int i = 0; i < 20000; ++i)
        {
            NdtShape s;
            SampleBatch b;
            b.reset({0, 0, 0});
            const Eigen::Vector3d c(u(rng) * 2, u(rng) * 2, 2 + u(rng));
            for (int k = 0; k < 6; ++k) b.add(c + Eigen::Vector3d(u(rng), u(rng), u(rng) * 0.2) * 0.05);
            s.merge(b, 0);
            const NdtGaussian g = NdtGaussian::fromShape(s, 1e-6);
            const Eigen::Vector3d o(u(rng) * 0.1, u(rng) * 0.1, 0);
            const Eigen::Vector3d end = c + Eigen::Vector3d(u(rng), u(rng), u(rng) + 0.3) * 0.08;
            const double sigma = 0.01 + 0.02 * std::abs(u(rng));
            const double ref = ndtMissDelta(g, o, end, sigma, model);
            const double got = rule(g.mean, g.info, o, end - o, end, sigma);
            ASSERT_EQ(std::memcmp(&ref, &got, sizeof(double)), 0) << ref << " vs " << got;
            nonzero += ref != 0.0;
        }
        if (min_lik < 1.0)
        {
            EXPECT_GT(nonzero, 100) << min_lik;
        }
    }
}

namespace
{
/// 64x48 camera at the origin looking along +z; x right, y down.
CameraIntrinsics smallCamera() { return {64, 48, 32.0, 32.0, 31.5, 23.5}; }
}  // namespace

TEST(SampleSums, IntegerSumsGiveTheDoubleShapeWithinFloatPrecision)
{
    // A tilted plane in front of the camera, one frame: each voxel's NDT shape
    // against the double mean and covariance of exactly its pixels' points.
    const CameraIntrinsics K = smallCamera();
    PanopticFrame f;
    f.K = K;
    f.depth.resize(K.width, K.height, 0.f);
    std::map<uint64_t, SampleBatch> ref;
    const VoxelGrid grid(0.1);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> noise(-0.004f, 0.004f);
    for (int r = 0; r < K.height; ++r)
        for (int c = 0; c < K.width; ++c)
        {
            const float z = 1.7f + 0.011f * float(c) + 0.006f * float(r) + noise(rng);
            f.depth.at(r, c) = z;
            const Eigen::Vector3d p = K.unproject(c, r, z);
            const VoxelKey k = grid.keyOf(p);
            auto it = ref.find(k.packed());
            if (it == ref.end())
            {
                it = ref.emplace(k.packed(), SampleBatch{}).first;
                it->second.reset(grid.center(k));
            }
            it->second.add(p);
        }
    PanopticMap map;
    map.integrate(f, Pose::Identity());
    size_t compared = 0;
    double worst = 0;  // relative scatter error
    for (const auto& [key, b] : ref)
    {
        const uint32_t vi = map.voxels().find(VoxelKey::unpack(key));
        ASSERT_NE(vi, kNoRecord);
        const NdtShape& s = map.shapeOf(map.voxels()[vi]);
        ASSERT_EQ(s.n, b.count);
        const Eigen::Vector3d m = b.mean();
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(s.mean[i], m[i], 2e-6);  // float storage of ~2 m: 2.4e-7
        if (b.count < 2) continue;
        const Eigen::Matrix3d C = b.scatter();
        const Eigen::Matrix3d S = s.scatter();
        // Each sample moved by at most half a quantum (0.05 um) per axis: the
        // scatter sum moves by at most ~n * voxel * quantum; float storage adds 1e-7.
        const double quantum = 0.1 / double(1 << kSampleBits);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                EXPECT_NEAR(S(i, j), C(i, j), double(b.count) * 0.1 * quantum + 2e-7 * std::abs(C(i, j)));
        worst = std::max(worst, (S - C).cwiseAbs().maxCoeff() / std::max(1e-12, C.cwiseAbs().maxCoeff()));
        ++compared;
    }
    EXPECT_GT(compared, 20u);
    std::printf("[measured] integer sample sums: largest relative scatter error %.2e over %zu voxels\n", worst,
                compared);
}

TEST(HistogramRuns, EqualOneAddPerPixelInPixelOrder)
{
    // Random classes and scores in runs, 3 frames (instances in the first): every
    // label and instance record must equal the one built by SparseHistogram::add,
    // pixel by pixel, to the bit. Quantised weights (PNDT_QUANTISED_HISTOGRAMS)
    // round once per run, not per pixel: the same ids in the same order, and
    // weights within a few of their 16-bit steps of the exact float sums.
    const CameraIntrinsics K = smallCamera();
    const ClassSet classes = ClassSet::nyuv2_40();
    MapOptions o;
    PanopticMap map(o);
    std::mt19937 rng(17);
    std::uniform_int_distribution<int> cls(0, 11), len(1, 7), inst(0, 4);
    std::uniform_real_distribution<float> score(0.6f, 1.0f);
    struct Expected
    {
        SparseHistogram<uint8_t, LabelRecord::kSemanticCapacity> semantic;  // float weights
        SparseHistogram<uint32_t, 16> instances;
        uint32_t n_l = 0, n_z = 0;
        bool has_rec = false, has_inst = false;
    };
    const auto expectWeight = [](float got, float want) {
        if constexpr (kQuantisedHistograms)
            EXPECT_NEAR(got, want, 2e-4f * std::max(1.f, want));
        else
            EXPECT_EQ(got, want);
    };
    std::map<uint64_t, Expected> expected;
    for (int frame = 0; frame < 3; ++frame)
    {
        PanopticFrame f;
        f.K = K;
        f.depth.resize(K.width, K.height, 2.0f);
        f.semantic.resize(K.width, K.height, 0);
        f.semantic_score.resize(K.width, K.height, 0.f);
        if (frame == 0)
        {
            f.instance.resize(K.width, K.height, 0);
            f.panoptic_score.resize(K.width, K.height, 0.f);
        }
        for (size_t i = 0; i < f.depth.data.size();)
        {
            const int n = len(rng);
            const uint16_t L = uint16_t(cls(rng));  // 0 = void, 1 wall (stuff), 2 floor (stuff), others things
            const uint32_t z = frame == 0 ? uint32_t(inst(rng)) * 1000 : 0;
            for (int k = 0; k < n && i < f.depth.data.size(); ++k, ++i)
            {
                f.semantic.data[i] = L;
                f.semantic_score.data[i] = score(rng);
                if (frame == 0)
                {
                    f.instance.data[i] = z;
                    f.panoptic_score.data[i] = score(rng) - 0.5f;  // some below theta_z = 0.1
                }
            }
        }
        // The expected records: new map ids 1, 2, ... in order of the predicted
        // ids' first pixel (all are new: the map has no instances yet).
        std::map<uint32_t, uint32_t> decision;
        if (frame == 0)
            for (uint32_t z : f.instance.data)
                if (z != 0 && !decision.count(z)) decision.emplace(z, uint32_t(decision.size()) + 1);
        for (int r = 0; r < K.height; ++r)
            for (int c = 0; c < K.width; ++c)
            {
                const size_t i = size_t(r) * K.width + c;
                const uint64_t key = map.grid().keyOf(K.unproject(c, r, 2.0)).packed();
                Expected& e = expected[key];
                if (frame == 0)
                {
                    const uint32_t z = f.instance.data[i];
                    const float sp = f.panoptic_score.data[i];
                    if (z != 0 && sp > float(o.theta_z))
                    {
                        e.has_rec = e.has_inst = true;
                        e.instances.add(decision.at(z), sp);
                        ++e.n_z;
                    }
                }
                const uint16_t L = f.semantic.data[i];
                const float sl = f.semantic_score.data[i];
                if (L != 0 && sl > float(o.theta_l))
                {
                    e.has_rec = true;
                    e.semantic.add(uint8_t(L), sl);
                    ++e.n_l;
                }
            }
        map.integrate(f, Pose::Identity());
    }
    size_t with_instances = 0;
    for (const auto& [key, e] : expected)
    {
        const uint32_t vi = map.voxels().find(VoxelKey::unpack(key));
        ASSERT_NE(vi, kNoRecord);
        const LabelRecord* r = map.labelsOf(map.voxels()[vi]);
        ASSERT_EQ(r != nullptr, e.has_rec);
        if (!r) continue;
        ASSERT_EQ(r->semantic.size(), e.semantic.size());
        EXPECT_EQ(0, std::memcmp(r->semantic.ids, e.semantic.ids, size_t(r->semantic.size())));
        for (int j = 0; j < r->semantic.size(); ++j) expectWeight(r->semantic.weight(j), e.semantic.weight(j));
        EXPECT_EQ(r->n_l, e.n_l);
        const InstanceRecord* in = map.instancesOf(*r);
        ASSERT_EQ(in != nullptr, e.has_inst);
        if (!in) continue;
        ++with_instances;
        ASSERT_EQ(in->hist.size(), e.instances.size());
        EXPECT_EQ(0, std::memcmp(in->hist.ids, e.instances.ids, sizeof(uint32_t) * in->hist.size()));
        for (int j = 0; j < in->hist.size(); ++j) expectWeight(in->hist.weight(j), e.instances.weight(j));
        EXPECT_EQ(in->n_z, e.n_z);
    }
    EXPECT_GT(with_instances, 10u);
}

TEST(MapOptionsThreads, ValidatedAndResolved)
{
    MapOptions o;
    EXPECT_EQ(o.threads, 1);
    o.threads = -1;
    EXPECT_THROW(o.validate(), std::invalid_argument);
    o.threads = 257;
    EXPECT_THROW(o.validate(), std::invalid_argument);
    o.threads = 0;
    EXPECT_NO_THROW(o.validate());
    EXPECT_GE(o.resolvedThreads(), 1);
    o.threads = 3;
    EXPECT_EQ(o.resolvedThreads(), 3);
}

TEST(PredictedPixels, HandCountedBand)
{
    // ids:   0  7  7  7  9  9  7  0  5
    // slots: 3  1 -1  2  4  4  1  0  2   (-1: no depth)
    const uint32_t ids[] = {0, 7, 7, 7, 9, 9, 7, 0, 5};
    const uint16_t sem[] = {1, 3, 3, 3, 4, 4, 3, 1, 6};
    const int32_t slots[] = {3, 1, -1, 2, 4, 4, 1, 0, 2};
    int32_t predicted[9];
    PredictedBand pb;
    assignPredicted(ids, sem, slots, predicted, 0, 9, pb, nullptr);
    EXPECT_EQ(std::vector<int32_t>(predicted, predicted + 9),
              (std::vector<int32_t>{-1, 0, kUnmappedPixel, 0, 1, 1, 0, -1, 2}));
    EXPECT_EQ(pb.ids, (std::vector<uint32_t>{7, 9, 5}));
    EXPECT_EQ(pb.area, (std::vector<uint64_t>{3, 2, 1}));  // mapped pixels only
    EXPECT_EQ(pb.cls, (std::vector<uint16_t>{3, 4, 6}));
}

TEST(PredictedPixels, TheFastPathsGiveTheScalarResults)
{
    std::vector<ContinueInstanceFn> fasts;
    if (const ContinueInstanceFn f = continueInstanceAvx512()) fasts.push_back(f);
    if (const ContinueInstanceFn f = continueInstanceAvx2()) fasts.push_back(f);
    if (fasts.empty()) GTEST_SKIP() << "no AVX2 or AVX-512 on this CPU";
    for (const ContinueInstanceFn fast : fasts)
    {
        std::mt19937 rng(5);
        const size_t n = 20000;
        std::vector<uint32_t> ids(n);
        std::vector<uint16_t> sem(n);
        std::vector<int32_t> slots(n);
        for (int trial = 0; trial < 20; ++trial)
        {
            // Runs of random length (1-80 pixels) of background or one of 12 ids;
            // holes without depth sprinkled at a per-trial rate.
            const double hole_rate = 0.02 * (trial % 4);
            std::uniform_real_distribution<double> u(0, 1);
            for (size_t i = 0; i < n;)
            {
                const uint32_t id = rng() % 3 == 0 ? 0 : 100 + rng() % 12;
                for (size_t e = std::min(n, i + 1 + rng() % 80); i < e; ++i)
                {
                    ids[i] = id;
                    sem[i] = uint16_t(id % 7);
                    slots[i] = u(rng) < hole_rate ? -1 : int32_t(rng() % 1000);
                }
            }
            // Bands that start and end off the 16-pixel grid.
            const size_t i0 = trial % 5, i1 = n - trial % 7;
            std::vector<int32_t> p_ref(n, 77), p_fast(n, 77);
            PredictedBand ref, got;
            assignPredicted(ids.data(), sem.data(), slots.data(), p_ref.data(), i0, i1, ref, nullptr);
            assignPredicted(ids.data(), sem.data(), slots.data(), p_fast.data(), i0, i1, got, fast);
            ASSERT_EQ(p_fast, p_ref) << "trial " << trial;
            ASSERT_EQ(got.ids, ref.ids);
            ASSERT_EQ(got.area, ref.area);
            ASSERT_EQ(got.cls, ref.cls);
        }
        // One instance throughout: the fast path settles every block by itself.
        std::fill(ids.begin(), ids.end(), 42u);
        std::vector<int32_t> p(n);
        uint64_t run = 5;
        ASSERT_EQ(fast(ids.data(), slots.data(), p.data(), n, 42, 3, run), n);
        uint64_t mapped = 0;
        for (size_t i = 0; i < n; ++i)
        {
            mapped += slots[i] >= 0;
            ASSERT_EQ(p[i], slots[i] >= 0 ? 3 : kUnmappedPixel);
        }
        EXPECT_EQ(run, 5 + mapped);
    }
}
