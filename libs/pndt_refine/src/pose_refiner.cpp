// NDT frame-to-map registration with Ceres (issue #22). See pose_refiner.h.
#include <pndt/refine/pose_refiner.h>
#include <pndt/voxel_key.h>

#include <ceres/sized_cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <tsl/robin_map.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pndt::refine
{
namespace
{
constexpr double kPi = 3.14159265358979323846;

double angleOf(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle(); }

/// One subsampled frame point and its current map Gaussian.
struct Assoc
{
    Eigen::Vector3d p;           ///< camera frame
    double weight = 1;           ///< class weight
    Eigen::Vector3d mu = Eigen::Vector3d::Zero();      ///< associated Gaussian's mean (world)
    Eigen::Matrix3d W = Eigen::Matrix3d::Zero();       ///< sqrt(weight) * L^T, info = L L^T
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< the Gaussian's smallest-variance axis (degeneracy test)
};

/// Searches the map Gaussian a world point belongs to; implemented by PoseRefiner::Impl.
struct GaussianSearch
{
    virtual ~GaussianSearch() = default;
    /// The nearest Gaussian (Mahalanobis, own voxel + 26 neighbours, within the gate) of frame
    /// point `i` moved to `x`, or nullptr.
    virtual const struct CachedGaussian* nearest(const Eigen::Vector3d& x, uint32_t i) = 0;
};


/// A map Gaussian as the refiner uses it.
struct CachedGaussian
{
    Eigen::Vector3d mu;
    Eigen::Matrix3d info;
    Eigen::Matrix3d LT;  ///< info = LT^T LT
    Eigen::Vector3d normal;
};

/// Point-to-distribution residual W (R p + t - mu) whose Gaussian is looked up at every
/// evaluation (the NDT score of the Gaussian the point currently falls into): associations
/// follow the pose inside one solve. Analytic Jacobians in Eigen's quaternion order (x, y, z, w).
class PointToDistribution final : public ceres::SizedCostFunction<3, 4, 3>
{
   public:
    PointToDistribution(GaussianSearch* search, const std::vector<Assoc>* points, uint32_t i)
        : search_(search), points_(points), i_(i)
    {
    }
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override
    {
        const double* q = parameters[0];
        const double* t = parameters[1];
        const Assoc& a = (*points_)[i_];
        const Eigen::Quaterniond Q(q[3], q[0], q[1], q[2]);
        const Eigen::Vector3d x = Q * a.p + Eigen::Vector3d(t[0], t[1], t[2]);
        const CachedGaussian* g = search_->nearest(x, i_);
        Eigen::Map<Eigen::Vector3d> r(residuals);
        if (!g)
        {
            r.setZero();
            if (jacobians)
            {
                if (jacobians[0]) std::fill(jacobians[0], jacobians[0] + 12, 0.0);
                if (jacobians[1]) std::fill(jacobians[1], jacobians[1] + 9, 0.0);
            }
            return true;
        }
        const double sw = std::sqrt(a.weight);
        const Eigen::Matrix3d W = sw * g->LT;
        r = W * (x - g->mu);
        if (jacobians)
        {
            if (jacobians[0])
            {
                // R(q) p = p + 2 w (v x p) + 2 v x (v x p) for q = (v, w), differentiated in (v, w)
                // (unnormalised: the manifold keeps q on the unit sphere).
                const Eigen::Vector3d v(q[0], q[1], q[2]);
                const double w = q[3];
                const Eigen::Vector3d& p = a.p;
                Eigen::Matrix3d px;
                px << 0, -p.z(), p.y(), p.z(), 0, -p.x(), -p.y(), p.x(), 0;
                Eigen::Matrix<double, 3, 4> dx;
                dx.leftCols<3>() = -2.0 * w * px +
                                   2.0 * (v.dot(p) * Eigen::Matrix3d::Identity() + v * p.transpose() - 2.0 * p * v.transpose());
                dx.col(3) = 2.0 * v.cross(p);
                Eigen::Map<Eigen::Matrix<double, 3, 4, Eigen::RowMajor>> jq(jacobians[0]);
                jq = W * dx;
            }
            if (jacobians[1])
            {
                Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> jt(jacobians[1]);
                jt = W;
            }
        }
        return true;
    }

   private:
    GaussianSearch* search_;
    const std::vector<Assoc>* points_;
    uint32_t i_;
};

struct Cell
{
    Eigen::Vector3d p;
    double d2;  ///< squared distance to the cube's centre
    uint16_t cls;
};
}  // namespace

const char* outcomeName(Outcome o)
{
    switch (o)
    {
        case Outcome::Accepted: return "accepted";
        case Outcome::Disabled: return "disabled";
        case Outcome::TooFewPoints: return "too-few-points";
        case Outcome::Degenerate: return "degenerate";
        case Outcome::NotConverged: return "not-converged";
        case Outcome::StepTooLarge: return "step-too-large";
        case Outcome::DriftTooLarge: return "drift-too-large";
    }
    return "?";
}

void RefineOptions::validate() const
{
    auto bad = [](const char* what) { throw std::invalid_argument(std::string("refine option ") + what); };
    if (subsample_voxel < 0) bad("subsample_voxel must be >= 0");
    if (pixel_step < 1) bad("pixel_step must be >= 1");
    if (max_points < 6) bad("max_points must be >= 6");
    if (!(max_depth > 0)) bad("max_depth must be > 0");
    if (!(loss_scale > 0)) bad("loss_scale must be > 0");
    if (!(gate_sigma > 0)) bad("gate_sigma must be > 0");
    if (!(min_sigma_ratio >= 0) || !(fine_sigma_ratio >= 0)) bad("min_sigma_ratio and fine_sigma_ratio must be >= 0");
    if (stuff_weight < 0 || thing_weight < 0 || void_weight < 0) bad("class weights must be >= 0");
    for (const auto& [c, w] : class_weights)
        if (w < 0) bad("class_weights must be >= 0");
    if (outer_iterations < 1 || max_iterations < 1) bad("iterations must be >= 1");
    if (min_points < 6) bad("min_points must be >= 6");
    if (min_eigen_ratio < 0 || min_eigen_ratio >= 1) bad("min_eigen_ratio must be at least 0 and below 1");
    if (!(max_step_translation > 0) || !(max_step_rotation > 0) || !(max_total_translation > 0) ||
        !(max_total_rotation > 0))
        bad("bounds must be > 0");
}

std::string RefineStats::summary() const
{
    std::ostringstream s;
    s << frames << " frames: " << accepted() << " refined, " << fallbacks() << " fell back";
    bool first = true;
    for (size_t i = 2; i < by_outcome.size(); ++i)
        if (by_outcome[i])
        {
            s << (first ? " (" : ", ") << outcomeName(Outcome(i)) << " " << by_outcome[i];
            first = false;
        }
    if (!first) s << ")";
    if (frames) s << ", " << 1000.0 * seconds / double(frames) << " ms/frame";
    return s.str();
}

/// The Gaussians around the voxel a frame point fell into when it was last looked up: a
/// point moves by millimetres between cost evaluations, so its 27-voxel neighbourhood is
/// searched in the map's voxel table only when it enters another voxel.
struct Neighbourhood
{
    VoxelKey key;
    bool valid = false;
    uint8_t count = 0;   ///< Gaussians among the 27 voxels (in search order)
    uint32_t begin = 0;  ///< first of them in Impl::candidates
};

struct PoseRefiner::Impl final : GaussianSearch
{
    const PanopticMap* map = nullptr;
    double min_var = 0, gate2 = 0;
    uint32_t min_samples = 0;
    std::vector<Neighbourhood> around;   ///< per frame point (index as in points)
    std::vector<uint32_t> candidates;    ///< indices into gauss, a run per Neighbourhood

    /// Forgets every point's neighbourhood (a new frame, or the Gaussians were rebuilt).
    void forgetNeighbourhoods(size_t n_points)
    {
        around.assign(n_points, Neighbourhood{});
        candidates.clear();
    }
    const CachedGaussian* nearest(const Eigen::Vector3d& x, uint32_t i) override
    {
        if (!map->grid().holds(x)) return nullptr;  // a diverged pose: no Gaussian near it
        const VoxelKey k = map->grid().keyOf(x);
        Neighbourhood& nb = around[i];
        if (!nb.valid || nb.key != k)
        {
            // Same search order as before the cache (z, y, x from -1): ties go the same way.
            nb.key = k;
            nb.valid = true;
            nb.begin = uint32_t(candidates.size());
            nb.count = 0;
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                    {
                        const uint32_t v = map->voxels().find(VoxelKey{k.x + dx, k.y + dy, k.z + dz});
                        if (v == kNoRecord) continue;
                        const uint32_t g = gaussianIndex(*map, v, min_var);
                        if (g == kNoRecord) continue;
                        candidates.push_back(g);
                        ++nb.count;
                    }
        }
        double best = gate2;
        const CachedGaussian* best_g = nullptr;
        for (uint32_t j = nb.begin, end = nb.begin + nb.count; j < end; ++j)
        {
            const CachedGaussian& g = gauss[candidates[j]];
            const Eigen::Vector3d d = x - g.mu;
            const double m2 = d.dot(g.info * d);
            if (m2 < best)
            {
                best = m2;
                best_g = &g;
            }
        }
        return best_g;
    }

    // The core's key mixer: std::hash<uint64_t> is the identity, and the table's power-of-two
    // mask kept only z's bits of a packed cube key (probe chains of thousands: 80 % of the time).
    tsl::robin_map<uint64_t, uint32_t, PackedKeyHash> cell_of;
    std::vector<Cell> cells;
    std::vector<Assoc> points;     ///< all subsampled points (p, weight)
    std::vector<Assoc> assoc;      ///< associated ones (what the costs read)
    tsl::robin_map<uint32_t, uint32_t> gauss_of;  ///< voxel -> index in gauss (kNoRecord: none)
    std::vector<CachedGaussian> gauss;
    std::vector<std::unique_ptr<PointToDistribution>> costs;
    std::unique_ptr<ceres::LossFunction> loss;
    ceres::EigenQuaternionManifold quaternion;
    std::vector<double> class_weight;  ///< by class id

    const PanopticMap* map_seen = nullptr;
    size_t map_voxels_seen = 0;

    uint32_t gaussianIndex(const PanopticMap& map, uint32_t voxel, double min_var)
    {
        const auto it = gauss_of.find(voxel);
        if (it != gauss_of.end()) return it->second;
        uint32_t idx = kNoRecord;
        const Voxel& v = map.voxels()[voxel];
        if (map.isOccupied(v) && map.hasGaussian(v) && map.shapeOf(v).n >= min_samples)
        {
            const NdtShape& s = map.shapeOf(v);
            CachedGaussian g;
            g.mu = s.meanVec();
            Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
            es.computeDirect(s.covariance());
            Eigen::Vector3d ev = es.eigenvalues().cwiseMax(0.0) + Eigen::Vector3d::Constant(min_var);
            g.normal = es.eigenvectors().col(0);
            const Eigen::Matrix3d V = es.eigenvectors();
            g.info = V * ev.cwiseInverse().asDiagonal() * V.transpose();
            g.LT = ev.cwiseInverse().cwiseSqrt().asDiagonal() * V.transpose();
            idx = uint32_t(gauss.size());
            gauss.push_back(g);
        }
        gauss_of.emplace(voxel, idx);
        return idx;
    }
};

PoseRefiner::PoseRefiner(RefineOptions options) : options_(std::move(options)), impl_(std::make_unique<Impl>())
{
    options_.validate();
    switch (options_.loss)
    {
        case RobustLoss::Cauchy: impl_->loss = std::make_unique<ceres::CauchyLoss>(options_.loss_scale); break;
        case RobustLoss::Huber: impl_->loss = std::make_unique<ceres::HuberLoss>(options_.loss_scale); break;
        case RobustLoss::None: break;
    }
}
PoseRefiner::~PoseRefiner() = default;
PoseRefiner::PoseRefiner(PoseRefiner&&) noexcept = default;
PoseRefiner& PoseRefiner::operator=(PoseRefiner&&) noexcept = default;

void PoseRefiner::reset()
{
    correction_ = Pose::Identity();
    stats_ = RefineStats{};
}

RefineResult PoseRefiner::refine(const PanopticMap& map, const PanopticFrame& frame, const Pose& T_ext)
{
    return refine(map, FrameView(frame), T_ext);
}

namespace
{
/// Depth in metres along z at (r, c) of a caller's view (uint16 units or float metres, z or
/// ray length), converted as the map converts it (frame_pixels.cpp: float units x scale, ray
/// lengths divided in double), so a view and the float frame it stands for refine alike.
/// Not positive or not finite = no depth.
double depthZ(const FrameView& f, int r, int c)
{
    const DepthView& d = f.depth;
    const size_t i = size_t(r) * d.rowStride() + size_t(c);
    const float v = d.is_uint16 ? float(static_cast<const uint16_t*>(d.data)[i]) * float(d.metres_per_unit)
                                : static_cast<const float*>(d.data)[i];
    if (d.measures == RangeKind::Z || !(v > 0.f) || !std::isfinite(v)) return v;
    const double x = (c - f.K.cx) / f.K.fx, y = (r - f.K.cy) / f.K.fy;
    return float(double(v) / std::sqrt(1.0 + x * x + y * y));  // ray length -> z
}
}  // namespace

RefineResult PoseRefiner::refine(const PanopticMap& map, const FrameView& frame, const Pose& T_ext)
{
    const auto t0 = std::chrono::steady_clock::now();
    Impl& m = *impl_;
    const RefineOptions& o = options_;
    RefineResult res;
    res.warm_start = o.carry_correction ? Pose(correction_ * T_ext) : T_ext;
    res.pose = res.warm_start;
    res.correction = correction_;
    auto finish = [&](Outcome out) -> RefineResult {
        res.outcome = out;
        if (out == Outcome::Accepted)
        {
            res.correction = res.pose * T_ext.inverse();
            if (o.carry_correction) correction_ = res.correction;
        }
        else
        {
            res.pose = o.fallback_keeps_correction ? res.warm_start : T_ext;
            res.correction = res.pose * T_ext.inverse();
        }
        res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        ++stats_.frames;
        ++stats_.by_outcome[size_t(out)];
        stats_.seconds += res.seconds;
        return res;
    };
    if (!o.enabled) return finish(Outcome::Disabled);

    // ---- class weights, per class id of the map's class set
    const ClassSet& classes = map.options().classes;
    if (m.class_weight.size() != classes.size())
    {
        m.class_weight.assign(classes.size(), o.stuff_weight);
        for (uint32_t c = 0; c < classes.size(); ++c)
            m.class_weight[c] = c == 0 ? o.void_weight : classes.isThing(c) ? o.thing_weight : o.stuff_weight;
        for (const auto& [c, w] : o.class_weights)
            if (c < m.class_weight.size()) m.class_weight[c] = w;
    }

    // ---- frame points, averaged per cube (camera frame)
    const double voxel = map.options().voxel_size;
    const double cube = o.subsample_voxel > 0 ? o.subsample_voxel : 0.5 * voxel;
    const CameraIntrinsics& K = frame.K;
    m.cell_of.clear();
    m.cells.clear();
    const bool labels = frame.hasLabels() && frame.semantic.width == frame.depth.width &&
                        frame.semantic.height == frame.depth.height;
    for (int r = 0; r < frame.depth.height; r += o.pixel_step)
        for (int c = 0; c < frame.depth.width; c += o.pixel_step)
        {
            const double z = depthZ(frame, r, c);
            if (!(z > 0) || z > o.max_depth) continue;
            const Eigen::Vector3d p = K.unproject(c, r, z);
            const int64_t kx = int64_t(std::floor(p.x() / cube)), ky = int64_t(std::floor(p.y() / cube)),
                          kz = int64_t(std::floor(p.z() / cube));
            const uint64_t key = (uint64_t(kx & 0x1FFFFF) << 42) | (uint64_t(ky & 0x1FFFFF) << 21) | uint64_t(kz & 0x1FFFFF);
            const uint16_t cls = labels ? frame.semantic.row(r)[c] : 0;
            // One real surface point per cube (the one nearest its centre): a cube's average
            // leaves the surface where it bends (corners, edges) and biases the registration.
            const Eigen::Vector3d centre = (Eigen::Vector3d(double(kx), double(ky), double(kz)) +
                                            Eigen::Vector3d::Constant(0.5)) * cube;
            const double d2 = (p - centre).squaredNorm();
            const auto [it, fresh] = m.cell_of.try_emplace(key, uint32_t(m.cells.size()));
            if (fresh)
                m.cells.push_back({p, d2, cls});
            else
            {
                Cell& cell = m.cells[it->second];
                if (d2 < cell.d2) cell = {p, d2, cls};
            }
        }
    const size_t n_cells = m.cells.size();
    const size_t stride = n_cells > o.max_points ? (n_cells + o.max_points - 1) / o.max_points : 1;
    m.points.clear();
    for (size_t i = 0; i < n_cells; i += stride)
    {
        const Cell& cell = m.cells[i];
        Assoc a;
        a.p = cell.p;
        a.weight = cell.cls < m.class_weight.size() ? m.class_weight[cell.cls] : o.void_weight;
        if (a.weight <= 0) continue;
        m.points.push_back(a);
    }
    res.points = uint32_t(m.points.size());

    // ---- Gaussian cache: valid while the map is the same and unchanged (one refine per frame
    // between integrations: rebuilt each call).
    m.gauss_of.clear();
    m.gauss.clear();
    const double min_sigma = std::max(o.min_sigma_ratio * voxel, 1e-4);
    const double min_var = min_sigma * min_sigma;

    double q[4], t[3];  // Eigen quaternion order x, y, z, w
    auto setParams = [&](const Pose& T) {
        const Eigen::Quaterniond Q(T.rotation());
        q[0] = Q.x(), q[1] = Q.y(), q[2] = Q.z(), q[3] = Q.w();
        t[0] = T.translation().x(), t[1] = T.translation().y(), t[2] = T.translation().z();
    };
    auto getParams = [&]() {
        Pose T = Pose::Identity();
        T.linear() = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
        T.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
        return T;
    };
    setParams(res.warm_start);
    Pose current = res.warm_start;
    const double gate2 = o.gate_sigma * o.gate_sigma;

    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = o.max_iterations;
    so.num_threads = 1;  // the costs share the Gaussian cache
    so.logging_type = ceres::SILENT;
    so.function_tolerance = 1e-5;   // relative cost change: sub-millimetre steps by then
    so.parameter_tolerance = 1e-6;
    so.minimizer_progress_to_stdout = false;

    m.map = &map;
    m.min_var = min_var;
    m.gate2 = gate2;
    m.min_samples = o.min_samples;
    // Gaussians are referenced by pointer during a solve: room for every voxel the points can reach.
    m.gauss.reserve(std::max(m.gauss.capacity(), m.points.size() * 27));
    m.forgetNeighbourhoods(m.points.size());
    auto associate = [&](const Pose& T) {
        m.assoc.clear();
        for (uint32_t i = 0; i < m.points.size(); ++i)
        {
            const Assoc& pt = m.points[i];
            const CachedGaussian* g = m.nearest(T * pt.p, i);
            if (!g) continue;
            Assoc a = pt;
            a.mu = g->mu;
            a.W = std::sqrt(pt.weight) * g->LT;
            a.normal = g->normal;
            m.assoc.push_back(a);
        }
        res.associated = uint32_t(m.assoc.size());
    };
    associate(current);
    if (m.assoc.size() < o.min_points) return finish(Outcome::TooFewPoints);
    while (m.costs.size() < m.points.size())
        m.costs.push_back(std::make_unique<PointToDistribution>(&m, &m.points, uint32_t(m.costs.size())));

    bool converged = false;
    bool first_cost = true;
    const bool fine = o.fine_sigma_ratio > 0 && o.fine_sigma_ratio < o.min_sigma_ratio;
    for (int outer = 0; outer < o.outer_iterations + (fine ? 1 : 0); ++outer)
    {
        if (fine && (converged || outer == o.outer_iterations))
        {
            // Coarse to fine: the wide Gaussians found the basin; the map's sharper ones finish.
            const double fs = std::max(o.fine_sigma_ratio * voxel, 1e-4);
            m.min_var = fs * fs;
            m.gauss_of.clear();
            m.gauss.clear();
            m.forgetNeighbourhoods(m.points.size());
        }
        ceres::Problem problem(po);
        problem.AddParameterBlock(q, 4, &m.quaternion);
        problem.AddParameterBlock(t, 3);
        for (size_t i = 0; i < m.points.size(); ++i) problem.AddResidualBlock(m.costs[i].get(), m.loss.get(), q, t);
        ceres::Solver::Summary summary;
        ceres::Solve(so, &problem, &summary);
        res.iterations += int(summary.iterations.size()) - 1;
        if (first_cost) res.initial_cost = summary.initial_cost;
        first_cost = false;
        res.final_cost = summary.final_cost;
        if (summary.termination_type == ceres::FAILURE || !summary.IsSolutionUsable())
            return finish(Outcome::NotConverged);
        const Pose next = getParams();
        const Pose delta = current.inverse() * next;
        current = next;
        if (std::getenv("PNDT_REFINE_DEBUG"))
            std::fprintf(stderr, "solve %d: cost %g -> %g, %zu it, %s, step %.5f m %.5f rad\n", outer,
                         summary.initial_cost, summary.final_cost, summary.iterations.size(),
                         ceres::TerminationTypeToString(summary.termination_type), delta.translation().norm(),
                         angleOf(delta.linear()));
        const bool done = summary.termination_type == ceres::CONVERGENCE ||
                          (delta.translation().norm() < 2e-4 && angleOf(delta.linear()) < 2e-4);
        if (fine && m.min_var != min_var)
            break;  // the fine solve was the last
        if (done)
        {
            converged = true;
            if (!fine) break;
        }
    }
    associate(current);
    res.pose = current;
    if (m.assoc.size() < o.min_points) return finish(Outcome::TooFewPoints);
    // ---- degeneracy: point-to-plane information along each Gaussian's normal, around the
    // points' centroid, rotation scaled by their RMS radius (unit-free eigenvalue ratio).
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    double wsum = 0;
    for (const Assoc& a : m.assoc)
    {
        centroid += a.weight * (current * a.p);
        wsum += a.weight;
    }
    centroid /= std::max(wsum, 1e-12);
    double r2 = 0;
    for (const Assoc& a : m.assoc) r2 += a.weight * ((current * a.p) - centroid).squaredNorm();
    const double rms = std::sqrt(r2 / std::max(wsum, 1e-12));
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    for (const Assoc& a : m.assoc)
    {
        const Eigen::Vector3d x = (current * a.p) - centroid;
        Eigen::Matrix<double, 6, 1> j;
        j.head<3>() = rms > 0 ? Eigen::Vector3d(x.cross(a.normal) / rms) : Eigen::Vector3d::Zero();
        j.tail<3>() = a.normal;
        H.noalias() += a.weight * j * j.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(H, Eigen::EigenvaluesOnly);
    const double emax = es.eigenvalues()(5);
    res.eigen_ratio = emax > 0 ? es.eigenvalues()(0) / emax : 0.0;
    if (res.eigen_ratio < o.min_eigen_ratio) return finish(Outcome::Degenerate);
    if (!converged) return finish(Outcome::NotConverged);

    // ---- bounds
    const Pose step = res.warm_start.inverse() * current;
    res.step_translation = step.translation().norm();
    res.step_rotation = angleOf(step.linear());
    if (res.step_translation > o.max_step_translation || res.step_rotation > o.max_step_rotation)
        return finish(Outcome::StepTooLarge);
    const Pose total = current * T_ext.inverse();
    const Pose total_cam = T_ext.inverse() * current;  // the correction in the camera frame: a world-frame
    (void)total;                                       // rotation far from the origin is a large translation
    if (total_cam.translation().norm() > o.max_total_translation || angleOf(total_cam.linear()) > o.max_total_rotation)
        return finish(Outcome::DriftTooLarge);
    (void)kPi;
    return finish(Outcome::Accepted);
}

TrajectoryError trajectoryError(const std::vector<Pose>& est, const std::vector<Pose>& truth, bool align, int delta)
{
    if (est.size() != truth.size()) throw std::invalid_argument("trajectoryError: trajectories differ in length");
    if (delta < 1) throw std::invalid_argument("trajectoryError: delta must be >= 1");
    TrajectoryError e;
    const size_t n = est.size();
    if (n == 0) return e;
    // Horn / Umeyama (no scale): truth ≈ R est + t.
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d tr = Eigen::Vector3d::Zero();
    if (align && n >= 3)
    {
        Eigen::Vector3d me = Eigen::Vector3d::Zero(), mt = Eigen::Vector3d::Zero();
        for (size_t i = 0; i < n; ++i)
        {
            me += est[i].translation();
            mt += truth[i].translation();
        }
        me /= double(n);
        mt /= double(n);
        Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
        for (size_t i = 0; i < n; ++i) C += (truth[i].translation() - mt) * (est[i].translation() - me).transpose();
        Eigen::JacobiSVD<Eigen::Matrix3d> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
        Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
        if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) S(2, 2) = -1;
        R = svd.matrixU() * S * svd.matrixV().transpose();
        tr = mt - R * me;
    }
    double se = 0;
    for (size_t i = 0; i < n; ++i) se += (R * est[i].translation() + tr - truth[i].translation()).squaredNorm();
    e.ate_rmse = std::sqrt(se / double(n));
    double st = 0, sr = 0;
    size_t m = 0;
    for (size_t i = 0; i + size_t(delta) < n; ++i)
    {
        const Pose dt = truth[i].inverse() * truth[i + delta];
        const Pose de = est[i].inverse() * est[i + delta];
        const Pose err = dt.inverse() * de;
        st += err.translation().squaredNorm();
        const double a = Eigen::AngleAxisd(err.linear()).angle();
        sr += a * a;
        ++m;
    }
    if (m)
    {
        e.rpe_translation = std::sqrt(st / double(m));
        e.rpe_rotation = std::sqrt(sr / double(m));
    }
    return e;
}

}  // namespace pndt::refine
