// Time offset between camera and localiser from refined poses. See time_offset.h.
#include <pndt/refine/time_offset.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace pndt::refine
{
namespace
{
/// Piecewise-linear external positions over the frame stamps.
struct Track
{
    const std::vector<double>& t;
    const std::vector<Eigen::Vector3d>& p;

    Eigen::Vector3d at(double s) const
    {
        const auto it = std::upper_bound(t.begin(), t.end(), s);
        const size_t j = size_t(std::clamp<std::ptrdiff_t>(it - t.begin(), 1, std::ptrdiff_t(t.size()) - 1));
        const double a = (s - t[j - 1]) / (t[j] - t[j - 1]);
        return p[j - 1] + a * (p[j] - p[j - 1]);
    }
    /// Central difference over ±h (smoother than one segment's slope under jitter).
    Eigen::Vector3d velocity(double s, double h) const { return (at(s + h) - at(s - h)) / (2 * h); }
};

/// Per window: r and v with the window's mean (or its line in time: intercept + slope per
/// axis) removed: the drift of the external poses is a slow random walk.
struct WindowSums
{
    size_t n = 0;
    double st = 0, stt = 0;
    Eigen::Vector3d sr = Eigen::Vector3d::Zero(), sv = Eigen::Vector3d::Zero();
    Eigen::Vector3d str = Eigen::Vector3d::Zero(), stv = Eigen::Vector3d::Zero();
    double srv = 0, svv = 0, srr = 0;

    void add(double t, const Eigen::Vector3d& r, const Eigen::Vector3d& v)
    {
        ++n;
        st += t;
        stt += t * t;
        sr += r;
        sv += v;
        str += t * r;
        stv += t * v;
        srv += r.dot(v);
        svv += v.squaredNorm();
        srr += r.squaredNorm();
    }
    /// Σ a'·b' for detrended a, b from their raw sums (Frisch-Waugh: regress out [1, t]).
    bool detrend = false;  ///< remove the line (else only the mean)
    double cross(double sab, const Eigen::Vector3d& sa, const Eigen::Vector3d& sb, const Eigen::Vector3d& sta,
                 const Eigen::Vector3d& stb) const
    {
        const double N = double(n), ctt = detrend ? stt - st * st / N : 0.0;
        const Eigen::Vector3d cta = sta - st * sa / N, ctb = stb - st * sb / N;
        return sab - sa.dot(sb) / N - (ctt > 0 ? cta.dot(ctb) / ctt : 0.0);
    }
    double rv() const { return cross(srv, sr, sv, str, stv); }
    double vv() const { return cross(svv, sv, sv, stv, stv); }
    double rr() const { return cross(srr, sr, sr, str, str); }
};

struct Fit
{
    size_t frames = 0, windows = 0;
    double num = 0, den = 0, rr = 0;  ///< Σ v'·r', Σ |v'|², Σ |r'|² over the windows
    std::vector<std::pair<double, double>> per_window;  ///< (num, den) of each window
};
}  // namespace

std::string TimeOffsetEstimate::summary() const
{
    std::ostringstream s;
    s.precision(3);
    if (!valid)
    {
        s << "not estimated (" << reason << ")";
        return s.str();
    }
    s << std::fixed << "poses match the camera " << offset * 1000 << " ms later than stamped (± "
      << standard_error * 1000 << " ms, " << frames << " frames; refined vs external "
      << rms_before * 100 << " -> " << rms_after * 100 << " cm rms); add " << -offset
      << " s to the pose stamps (--clock-offset)";
    return s.str();
}

void TimeOffsetEstimator::add(double t, const Pose& external, const Pose& refined, bool accepted)
{
    if (!std::isfinite(t) || (!t_.empty() && t <= t_.back())) return;  // out of order: the track needs rising stamps
    t_.push_back(t);
    external_.push_back(external.translation());
    refined_.push_back(refined.translation());
    accepted_.push_back(accepted ? 1 : 0);
}

void TimeOffsetEstimator::clear()
{
    t_.clear();
    external_.clear();
    refined_.clear();
    accepted_.clear();
}

TimeOffsetEstimate TimeOffsetEstimator::estimate() const
{
    TimeOffsetEstimate e;
    const size_t n = t_.size();
    size_t accepted = 0;
    for (char a : accepted_) accepted += size_t(a);
    if (n < 3 || accepted < options_.min_frames)
    {
        e.reason = std::to_string(accepted) + " refined frames, " + std::to_string(options_.min_frames) + " needed";
        return e;
    }
    std::vector<double> periods(n - 1);
    for (size_t i = 0; i + 1 < n; ++i) periods[i] = t_[i + 1] - t_[i];
    std::nth_element(periods.begin(), periods.begin() + periods.size() / 2, periods.end());
    const double h = periods[periods.size() / 2];
    const Track track{t_, external_};
    const double lo = t_.front() + h, hi = t_.back() - h;

    auto fit = [&](double delta) {
        std::map<long, WindowSums> windows;
        for (size_t i = 0; i < n; ++i)
        {
            const double s = t_[i] + delta;
            if (!accepted_[i] || s < lo || s > hi) continue;
            const long w = long(std::floor((t_[i] - t_.front()) / options_.window_seconds));
            windows[w].detrend = options_.detrend;
            windows[w].add(t_[i] - t_.front() - double(w) * options_.window_seconds, refined_[i] - track.at(s),
                           track.velocity(s, h));
        }
        Fit f;
        for (const auto& [k, w] : windows)
        {
            if (w.n < 3) continue;  // two frames: the window's line takes them all
            ++f.windows;
            f.frames += w.n;
            f.num += w.rv();
            f.den += w.vv();
            f.rr += w.rr();
            f.per_window.emplace_back(w.rv(), w.vv());
        }
        return f;
    };

    const Fit first = fit(0.0);
    double delta = 0;
    Fit f = first;
    for (int it = 0; it < 30; ++it)
    {
        if (f.frames < options_.min_frames || !(f.den > 0))
        {
            e.reason = "too little change of velocity within the windows";
            return e;
        }
        const double step = f.num / f.den;
        delta += step;
        if (std::abs(delta) > options_.max_offset)
        {
            e.reason = "estimate beyond " + std::to_string(options_.max_offset) + " s";
            return e;
        }
        f = fit(delta);
        if (std::abs(step) < 1e-6) break;
    }
    e.frames = f.frames;
    e.offset = delta;
    e.rms_before = std::sqrt(std::max(first.rr, 0.0) / double(std::max<size_t>(first.frames, 1)));
    e.rms_after = std::sqrt(std::max(f.rr, 0.0) / double(std::max<size_t>(f.frames, 1)));
    if (f.windows < 3)
    {
        e.reason = "fewer than 3 windows of " + std::to_string(options_.window_seconds) + " s";
        return e;
    }
    // Jackknife over windows (drift and refinement errors are correlated within a window, so
    // the residuals are not independent frame by frame): the spread of the estimate without
    // each window in turn.
    double mean = 0;
    std::vector<double> loo;
    for (const auto& [num, den] : f.per_window)
        if (f.den - den > 0) loo.push_back((f.num - num) / (f.den - den));
    for (double x : loo) mean += x / double(loo.size());
    double var = 0;
    for (double x : loo) var += (x - mean) * (x - mean);
    const double W = double(loo.size());
    e.standard_error = W >= 3 ? std::sqrt((W - 1) / W * var) : std::numeric_limits<double>::infinity();
    if (!(e.standard_error <= options_.max_standard_error))
    {
        e.reason = "not observable: ±" + std::to_string(e.standard_error) + " s";
        return e;
    }
    e.valid = true;
    return e;
}

}  // namespace pndt::refine
