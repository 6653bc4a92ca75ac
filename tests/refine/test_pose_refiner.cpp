// Frame-to-map pose refinement on an analytic room: recovery of a known perturbation,
// an exact pose stays put, a single plane is refused, fallbacks are counted.
#include <gtest/gtest.h>
#include <pndt/look_at.h>
#include <pndt/panoptic_map.h>
#include <pndt/refine/pose_refiner.h>

#include <cmath>
#include <limits>

namespace
{
using pndt::Pose;

// A box room [-2,2] x [-1.5,2.5] x [0,2.6] (z up) with a cabinet [0.6,1.4] x [1.6,2.5] x [0,1.2].
struct Box
{
    Eigen::Vector3d lo, hi;
};
const Box kRoom{{-2, -1.5, 0}, {2, 2.5, 2.6}};
const Box kCabinet{{0.6, 1.6, 0}, {1.4, 2.5, 1.2}};

/// Distance along d from o (inside the room) to the room's walls.
double exitDistance(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d)
{
    double t = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a)
    {
        if (d[a] > 1e-12) t = std::min(t, (b.hi[a] - o[a]) / d[a]);
        if (d[a] < -1e-12) t = std::min(t, (b.lo[a] - o[a]) / d[a]);
    }
    return t;
}
/// Entry distance of the ray into a box (slab test), infinity when missed.
double entryDistance(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d)
{
    double t0 = 0, t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a)
    {
        if (std::abs(d[a]) < 1e-12)
        {
            if (o[a] < b.lo[a] || o[a] > b.hi[a]) return std::numeric_limits<double>::infinity();
            continue;
        }
        double ta = (b.lo[a] - o[a]) / d[a], tb = (b.hi[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1 && t0 > 0 ? t0 : std::numeric_limits<double>::infinity();
}

pndt::CameraIntrinsics intrinsics()
{
    pndt::CameraIntrinsics K;
    K.width = 160;
    K.height = 120;
    K.fx = K.fy = 110;
    K.cx = 79.5;
    K.cy = 59.5;
    return K;
}

/// Optical camera at `eye` looking at `target`, world z up.
Pose lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target)
{
    return pndt::lookAt(eye, target, Eigen::Vector3d::UnitZ());
}

/// Depth of the room (and the cabinet) seen from T; `plane_only`: an infinite wall at y = 2.5 only.
pndt::PanopticFrame render(const Pose& T, bool plane_only = false)
{
    pndt::PanopticFrame f;
    f.K = intrinsics();
    f.depth = pndt::Image<float>(f.K.width, f.K.height, 0.f);
    f.semantic = pndt::Image<uint16_t>(f.K.width, f.K.height, 0);
    for (int r = 0; r < f.K.height; ++r)
        for (int c = 0; c < f.K.width; ++c)
        {
            const Eigen::Vector3d dc = f.K.unproject(c, r, 1.0);
            const Eigen::Vector3d d = T.linear() * dc;
            const Eigen::Vector3d o = T.translation();
            double t;
            uint16_t cls = 1;  // wall
            if (plane_only)
                t = d.y() > 1e-9 ? (2.5 - o.y()) / d.y() : std::numeric_limits<double>::infinity();
            else
            {
                t = exitDistance(kRoom, o, d);
                const Eigen::Vector3d hit = o + t * d;
                if (std::abs(hit.z()) < 1e-6) cls = 2;                // floor
                else if (std::abs(hit.z() - 2.6) < 1e-6) cls = 22;    // ceiling
                const double tc = entryDistance(kCabinet, o, d);
                if (tc < t)
                {
                    t = tc;
                    cls = 3;  // cabinet (a thing)
                }
            }
            const double z = t * dc.z();
            if (std::isfinite(z) && z < 8)
            {
                f.depth.at(r, c) = float(z);
                f.semantic.at(r, c) = cls;
            }
        }
    return f;
}

pndt::PanopticMap buildMap(const std::vector<Pose>& poses, bool plane_only = false)
{
    pndt::MapOptions mo;
    mo.voxel_size = 0.10;
    pndt::PanopticMap map(mo);
    for (const Pose& T : poses)
    {
        pndt::PanopticFrame f = render(T, plane_only);
        f.semantic = {};  // geometry only: labels are not what is tested here
        map.integrate(f, T);
    }
    return map;
}

const Eigen::Vector3d kEye(-0.8, -0.6, 1.3);
const Eigen::Vector3d kTarget(1.0, 2.5, 0.6);  // a corner: floor and two walls, the cabinet

std::vector<Pose> mappingPoses()
{
    return {lookAt(kEye, kTarget), lookAt(kEye + Eigen::Vector3d(0.2, 0.0, 0.05), kTarget + Eigen::Vector3d(-0.4, 0, 0)),
            lookAt(kEye + Eigen::Vector3d(-0.2, 0.1, -0.05), kTarget + Eigen::Vector3d(0.3, 0, 0.2))};
}

Pose perturb(const Pose& T, const Eigen::Vector3d& dt, const Eigen::Vector3d& axis, double angle)
{
    Pose D = Pose::Identity();
    D.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
    D.translation() = dt;
    return T * D;
}

double angleBetween(const Pose& a, const Pose& b) { return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle(); }

pndt::refine::RefineOptions enabled()
{
    pndt::refine::RefineOptions o;
    o.enabled = true;
    return o;
}
/// A basin for a 3 cm / 1.5 deg error in one frame (the defaults, chosen on noisy generated
/// sequences, gate at 2 sigmas: a frame's error after the carried correction is smaller).
pndt::refine::RefineOptions wideBasin()
{
    pndt::refine::RefineOptions o = enabled();
    o.gate_sigma = 6;
    o.loss_scale = 2;
    return o;
}

constexpr double kDeg = 3.14159265358979323846 / 180.0;

TEST(PoseRefiner, RecoversKnownPerturbation)
{
    const pndt::PanopticMap map = buildMap(mappingPoses());
    const Pose truth = lookAt(kEye + Eigen::Vector3d(0.1, 0.05, 0.0), kTarget + Eigen::Vector3d(0.1, 0, 0.1));
    const pndt::PanopticFrame f = render(truth);
    const Pose external = perturb(truth, {0.03, -0.02, 0.025}, {0.3, 1.0, -0.4}, 1.5 * kDeg);
    pndt::refine::PoseRefiner refiner(wideBasin());
    const auto r = refiner.refine(map, f, external);
    ASSERT_EQ(r.outcome, pndt::refine::Outcome::Accepted) << pndt::refine::outcomeName(r.outcome);
    EXPECT_LT((r.pose.translation() - truth.translation()).norm(), 0.005);
    EXPECT_LT(angleBetween(r.pose, truth), 0.2 * kDeg);
    // The correction is carried: the next frame starts from it.
    EXPECT_TRUE(refiner.correction().isApprox(r.pose * external.inverse(), 1e-9));
    EXPECT_EQ(refiner.stats().accepted(), 1u);
}

TEST(PoseRefiner, ExactPoseStaysPut)
{
    const pndt::PanopticMap map = buildMap(mappingPoses());
    const Pose truth = lookAt(kEye + Eigen::Vector3d(-0.1, 0.05, 0.02), kTarget);
    pndt::refine::PoseRefiner refiner(enabled());
    const auto r = refiner.refine(map, render(truth), truth);
    ASSERT_EQ(r.outcome, pndt::refine::Outcome::Accepted) << pndt::refine::outcomeName(r.outcome);
    EXPECT_LT((r.pose.translation() - truth.translation()).norm(), 0.002);
    EXPECT_LT(angleBetween(r.pose, truth), 0.1 * kDeg);
}

TEST(PoseRefiner, SinglePlaneIsRefused)
{
    // Facing a wall straight on: nothing pins the motion along the wall or the turn about its normal.
    const Eigen::Vector3d eye(0, 0, 1.3), target(0, 2.5, 1.3);
    const pndt::PanopticMap map = buildMap({lookAt(eye, target), lookAt(eye + Eigen::Vector3d(0.1, 0, 0), target)}, true);
    const Pose truth = lookAt(eye + Eigen::Vector3d(0.05, 0.1, 0), target);
    const Pose external = perturb(truth, {0.02, 0.01, 0.0}, {0, 0, 1}, 0.5 * kDeg);
    pndt::refine::PoseRefiner refiner(enabled());
    const auto r = refiner.refine(map, render(truth, true), external);
    EXPECT_EQ(r.outcome, pndt::refine::Outcome::Degenerate) << pndt::refine::outcomeName(r.outcome)
                                                             << " ratio " << r.eigen_ratio;
    EXPECT_TRUE(r.pose.isApprox(external, 1e-12));  // fell back to the (uncorrected) warm start
    EXPECT_EQ(refiner.stats().fallbacks(), 1u);
    EXPECT_EQ(refiner.stats().by_outcome[size_t(pndt::refine::Outcome::Degenerate)], 1u);
}

TEST(PoseRefiner, FallbackPathIsCounted)
{
    pndt::refine::PoseRefiner refiner(enabled());
    const Pose truth = lookAt(kEye, kTarget);
    // An empty map: too few Gaussians.
    const pndt::PanopticMap empty;
    auto r = refiner.refine(empty, render(truth), truth);
    EXPECT_EQ(r.outcome, pndt::refine::Outcome::TooFewPoints);
    EXPECT_TRUE(r.pose.isApprox(truth, 1e-12));
    // A correction beyond the per-frame bound is refused and the warm start kept.
    auto o = wideBasin();
    o.max_step_translation = 0.01;
    pndt::refine::PoseRefiner bounded(o);
    const pndt::PanopticMap map = buildMap(mappingPoses());
    const Pose external = perturb(truth, {0.04, 0.0, 0.0}, {0, 0, 1}, 0.0);
    r = bounded.refine(map, render(truth), external);
    EXPECT_EQ(r.outcome, pndt::refine::Outcome::StepTooLarge);
    EXPECT_TRUE(r.pose.isApprox(external, 1e-12));
    EXPECT_TRUE(bounded.correction().isApprox(Pose::Identity(), 1e-12));
    EXPECT_EQ(refiner.stats().fallbacks() + bounded.stats().fallbacks(), 2u);
    // Disabled: the external pose, not counted as a fallback.
    pndt::refine::PoseRefiner off;
    r = off.refine(map, render(truth), external);
    EXPECT_EQ(r.outcome, pndt::refine::Outcome::Disabled);
    EXPECT_EQ(off.stats().fallbacks(), 0u);
}

TEST(PoseRefiner, CameraBuffersRefineAsTheFloatFrame)
{
    // uint16 millimetres and float ray lengths in the caller's (strided) buffers, through
    // FrameView: the same pose as the float frame of the same depths (the map's conversion).
    const pndt::PanopticMap map = buildMap(mappingPoses());
    const Pose truth = lookAt(kEye + Eigen::Vector3d(0.1, 0.05, 0.0), kTarget + Eigen::Vector3d(0.1, 0, 0.1));
    const pndt::PanopticFrame rendered = render(truth);
    const int W = rendered.K.width, H = rendered.K.height;
    const size_t stride = size_t(W) + 7;
    std::vector<uint16_t> mm(stride * size_t(H), 0);
    std::vector<float> ray(stride * size_t(H), 0.f);
    pndt::PanopticFrame as_float = rendered;  // the depths the uint16 view stands for
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
        {
            const float z = rendered.depth.at(r, c);
            mm[size_t(r) * stride + size_t(c)] = uint16_t(std::lround(z * 1000.f));
            as_float.depth.at(r, c) = float(mm[size_t(r) * stride + size_t(c)]) * 0.001f;
            ray[size_t(r) * stride + size_t(c)] = float(double(z) * rendered.K.unproject(c, r, 1.0).norm());
        }
    const Pose external = perturb(truth, {0.02, -0.01, 0.015}, {0.3, 1.0, -0.4}, 1.0 * kDeg);
    auto refineWith = [&](auto&& frame) { return pndt::refine::PoseRefiner(wideBasin()).refine(map, frame, external); };
    const auto from_float = refineWith(as_float);
    ASSERT_EQ(from_float.outcome, pndt::refine::Outcome::Accepted);

    pndt::FrameView view(rendered);
    view.depth = pndt::DepthView::units(mm.data(), W, H, 0.001, stride);
    const auto from_mm = refineWith(view);
    ASSERT_EQ(from_mm.outcome, pndt::refine::Outcome::Accepted);
    EXPECT_TRUE(from_mm.pose.isApprox(from_float.pose, 1e-12));
    EXPECT_EQ(from_mm.points, from_float.points);

    view.depth = pndt::DepthView::metres(ray.data(), W, H, stride, pndt::RangeKind::Ray);
    const auto from_ray = refineWith(view);
    ASSERT_EQ(from_ray.outcome, pndt::refine::Outcome::Accepted);
    EXPECT_LT((from_ray.pose.translation() - truth.translation()).norm(), 0.005);
    EXPECT_LT(angleBetween(from_ray.pose, truth), 0.2 * kDeg);
    EXPECT_LT((from_ray.pose.translation() - refineWith(rendered).pose.translation()).norm(), 1e-4);
}

TEST(PoseRefiner, BadOptionsThrow)
{
    auto o = enabled();
    o.loss_scale = 0;
    EXPECT_THROW(pndt::refine::PoseRefiner{o}, std::invalid_argument);
}

TEST(TrajectoryError, AlignedAteIgnoresARigidOffset)
{
    std::vector<Pose> truth, est;
    Pose offset = Pose::Identity();
    offset.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    offset.translation() = Eigen::Vector3d(1, 2, 3);
    for (int i = 0; i < 20; ++i)
    {
        Pose T = Pose::Identity();
        T.translation() = Eigen::Vector3d(0.1 * i, std::sin(0.3 * i), 0.05 * i * i * 0.01);
        truth.push_back(T);
        est.push_back(offset * T);
    }
    const auto e = pndt::refine::trajectoryError(est, truth);
    EXPECT_LT(e.ate_rmse, 1e-9);
    EXPECT_LT(e.rpe_translation, 1e-9);
    est[10].translation() += Eigen::Vector3d(0.1, 0, 0);
    const auto u = pndt::refine::trajectoryError(est, truth, false);
    EXPECT_GT(u.ate_rmse, 1.0);
}

}  // namespace
