#include "carrier_run.h"

#include <fmt/format.h>
#include <pndt/mrpt/observation_frame.h>

#include <algorithm>
#include <chrono>
#include <random>

namespace pndt::bench
{
namespace
{
template <typename F>
double fastestMs(int repeat, F&& f)
{
    double best = 1e30;
    for (int i = 0; i < repeat; ++i)
    {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
}
}  // namespace

void runCarriers(int W, int H, int repeat)
{
    std::mt19937 rng(1);
    PanopticFrame f;
    f.K = {W, H, 525.0 * W / 640, 525.0 * W / 640, (W - 1) / 2.0, (H - 1) / 2.0};
    f.depth.resize(W, H);
    f.semantic.resize(W, H);
    f.semantic_score.resize(W, H);
    f.instance.resize(W, H);
    f.panoptic_score.resize(W, H);
    for (size_t i = 0; i < f.depth.size(); ++i)
    {
        f.depth.data[i] = i % 17 ? 0.5f + float(rng() % 4000) * 0.001f : 0.f;  // every 17th pixel no depth
        f.semantic.data[i] = uint16_t(rng() % 41);
        f.semantic_score.data[i] = float(rng() % 1000) * 0.001f;
        f.instance.data[i] = rng() % 3 ? 0 : 65536 + rng() % 30;
        f.panoptic_score.data[i] = float(rng() % 1000) * 0.001f;
    }
    mrpt::obs::CObservation3DRangeScan scan;
    rangeScanFrom(f, scan);
    mrpt::obs::CObservationImage sem, inst;
    labelImagesFrom(f, "RGBD", mrpt::Clock::now(), sem, inst);
    PanopticFrame out;
    const double depth_z = fastestMs(repeat, [&] { depthFrameFrom(scan, out); });
    scan.range_is_depth = false;
    const double depth_ray = fastestMs(repeat, [&] { depthFrameFrom(scan, out); });
    const double decode = fastestMs(repeat, [&] { attachPanopticLabels(sem, inst, out); });
    const double encode = fastestMs(repeat, [&] { labelImagesFrom(f, "RGBD", mrpt::Clock::now(), sem, inst); });
    fmt::print("carriers {}x{} (fastest of {}, ms a frame): depthFrameFrom z {:.3f}, ray length {:.3f}; "
               "attachPanopticLabels (decode) {:.3f}; labelImagesFrom (encode) {:.3f}\n",
               W, H, repeat, depth_z, depth_ray, decode, encode);
}
}  // namespace pndt::bench
