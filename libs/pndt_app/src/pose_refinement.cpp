#include <fmt/format.h>
#include <pndt/app/pose_refinement.h>
#include <pndt/io/atomic_file.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pndt::app
{
namespace
{
double number(const std::string& key, const std::string& v)
{
    size_t used = 0;
    double x = 0;
    try
    {
        x = std::stod(v, &used);
    }
    catch (const std::exception&)
    {
        used = 0;
    }
    if (used != v.size() || v.empty()) throw std::invalid_argument("refine option " + key + ": not a number: '" + v + "'");
    return x;
}
bool boolean(const std::string& key, const std::string& v)
{
    if (v == "true" || v == "1" || v == "yes") return true;
    if (v == "false" || v == "0" || v == "no") return false;
    throw std::invalid_argument("refine option " + key + ": not a boolean: '" + v + "'");
}
}  // namespace

void setRefineOption(refine::RefineOptions& o, const std::string& kv)
{
    const size_t eq = kv.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("refine option '" + kv + "': expected key=value");
    const std::string k = kv.substr(0, eq), v = kv.substr(eq + 1);
    auto num = [&] { return number(k, v); };
    if (k == "loss")
    {
        if (v == "cauchy") o.loss = refine::RobustLoss::Cauchy;
        else if (v == "huber") o.loss = refine::RobustLoss::Huber;
        else if (v == "none") o.loss = refine::RobustLoss::None;
        else throw std::invalid_argument("refine option loss: cauchy, huber or none, not '" + v + "'");
    }
    else if (k == "loss_scale") o.loss_scale = num();
    else if (k == "gate_sigma") o.gate_sigma = num();
    else if (k == "min_sigma_ratio") o.min_sigma_ratio = num();
    else if (k == "fine_sigma_ratio") o.fine_sigma_ratio = num();
    else if (k == "min_samples") o.min_samples = uint32_t(num());
    else if (k == "stuff_weight") o.stuff_weight = num();
    else if (k == "thing_weight") o.thing_weight = num();
    else if (k == "void_weight") o.void_weight = num();
    else if (k == "class_weight")
    {
        const size_t c = v.find(':');
        if (c == std::string::npos) throw std::invalid_argument("refine option class_weight: expected <id>:<weight>");
        o.class_weights.emplace_back(uint16_t(number(k, v.substr(0, c))), number(k, v.substr(c + 1)));
    }
    else if (k == "max_points") o.max_points = uint32_t(num());
    else if (k == "pixel_step") o.pixel_step = int(num());
    else if (k == "subsample_voxel") o.subsample_voxel = num();
    else if (k == "max_depth") o.max_depth = num();
    else if (k == "outer_iterations") o.outer_iterations = int(num());
    else if (k == "max_iterations") o.max_iterations = int(num());
    else if (k == "min_points") o.min_points = uint32_t(num());
    else if (k == "min_eigen_ratio") o.min_eigen_ratio = num();
    else if (k == "max_step_translation") o.max_step_translation = num();
    else if (k == "max_step_rotation") o.max_step_rotation = num();
    else if (k == "max_total_translation") o.max_total_translation = num();
    else if (k == "max_total_rotation") o.max_total_rotation = num();
    else if (k == "carry_correction") o.carry_correction = boolean(k, v);
    else if (k == "fallback_keeps_correction") o.fallback_keeps_correction = boolean(k, v);
    else throw std::invalid_argument("unknown refine option '" + k + "'");
}

FramePoseRefinement::FramePoseRefinement(refine::RefineOptions options) : refiner_(std::move(options)) {}

Pose FramePoseRefinement::refine(const PanopticMap* map, const PanopticFrame& frame, const Pose& T, double t)
{
    static const PanopticMap kEmpty;
    const refine::RefineResult r = refiner_.refine(map ? *map : kEmpty, frame, T);
    poses_.emplace_back(t, r.pose);
    time_offset_.add(t, T, r.pose, r.accepted());
    return r.pose;
}

void FramePoseRefinement::writeTum(const std::string& path) const
{
    io::writeFileAtomically(path, [&](const std::string& tmp) {
        std::ofstream f(tmp);
        f << "# refined optical camera poses (pndt-map --refine): timestamp tx ty tz qx qy qz qw\n";
        f << "# camera / localiser time offset: " << timeOffset().summary() << "\n";
        for (const auto& [t, T] : poses_)
        {
            const Eigen::Quaterniond q(T.rotation());
            f << fmt::format("{:.6f} {:.6f} {:.6f} {:.6f} {:.9f} {:.9f} {:.9f} {:.9f}\n", t, T.translation().x(),
                             T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(), q.w());
        }
        io::closeWrittenStream(f, path);
    });
}

}  // namespace pndt::app
