#include "evaluate_frames.h"

#include <fmt/format.h>
#include <pndt/eval/label_png.h>
#include <pndt/eval/map_eval.h>
#include <pndt/eval/panoptic_codec.h>
#include <pndt/io/sequence.h>

#include <filesystem>
#include <unordered_map>

namespace pndt::evalapp
{
namespace fs = std::filesystem;

FrameScores evaluateFrames(const PanopticMap& map, const std::string& split_dir, const std::string& sequence,
                           const eval::Benchmark& bench, int every, const std::string& export_dir)
{
    const io::RgbdSequence seq = io::openNicrSequence(split_dir, sequence);
    const InstanceNumbering numbering = InstanceNumbering::of(map);
    std::unordered_map<uint32_t, double> confidence_of;
    for (const MapInstance& mi : map.instances()) confidence_of[mi.id] = mi.confidence;
    const eval::InstanceConfidence confidence = [&](uint16_t, uint32_t id) { return confidence_of.at(id); };
    eval::PanopticEvaluator ev(bench);
    FrameScores s;
    RenderedView view;
    io::FrameLoadOptions load;
    load.color = false;
    load.predictions = false;
    for (size_t i = 0; i < seq.size(); i += size_t(std::max(1, every)))
    {
        const io::FrameRecord& rec = seq.frames[i];
        if (!rec.T_world_cam)
        {
            ++s.skipped_no_pose;
            continue;
        }
        if (rec.semantic_path.empty())
        {
            ++s.skipped_no_gt;
            continue;
        }
        const io::RgbdFrame f = seq.load(i, load);
        // Named with its file here (the evaluator would only give a pixel index).
        for (size_t k = 0; k < f.semantic_gt.data.size(); ++k)
            if (f.semantic_gt.data[k] >= bench.classes().size())
                throw InputError(fmt::format("{}: pixel (row {}, col {}): class {} is outside the benchmark's classes 0..{}",
                                             rec.semantic_path, k / size_t(f.semantic_gt.width),
                                             k % size_t(f.semantic_gt.width), f.semantic_gt.data[k],
                                             bench.classes().size() - 1));
        Image<uint32_t> gt_instance;
        gt_instance.resize(f.semantic_gt.width, f.semantic_gt.height, 0u);
        if (!f.instance_gt.data.empty())
            for (size_t k = 0; k < gt_instance.data.size(); ++k) gt_instance.data[k] = f.instance_gt.data[k];
        // GT labels are given at the GT image's size: render the map at that size.
        // (ScanNet labels its colour images, Hypersim depth and colour alike.)
        CameraIntrinsics K = f.semantic_gt.sameSize(f.K_color.width, f.K_color.height) ? f.K_color : f.K;
        if (!f.semantic_gt.sameSize(K.width, K.height))
        {
            const double sx = double(f.semantic_gt.width) / K.width, sy = double(f.semantic_gt.height) / K.height;
            K = {f.semantic_gt.width, f.semantic_gt.height, K.fx * sx, K.fy * sy, (K.cx + 0.5) * sx - 0.5,
                 (K.cy + 0.5) * sy - 0.5};
        }
        const eval::PredictedLabels pred =
            eval::evaluateView(map, *rec.T_world_cam, K, f.semantic_gt, gt_instance, ev, &view, confidence);
        ++s.frames;
        if (!export_dir.empty())
        {
            Image<uint16_t> sem;
            Image<uint32_t> ins;
            sem.resize(K.width, K.height, 0);
            ins.resize(K.width, K.height, 0u);
            for (size_t k = 0; k < pred.panoptic.size(); ++k)
            {
                sem.data[k] = eval::semanticOf(pred.panoptic[k]);
                ins.data[k] = eval::instanceOf(pred.panoptic[k]);
            }
            const fs::path dir = fs::path(export_dir) / "panoptic_2d";
            fs::create_directories(dir);
            eval::writePanopticPng((dir / (rec.id + ".png")).string(), sem, ins);
        }
    }
    if (s.frames == 0)
        throw InputError(fmt::format("{}/{}: no frame with a pose and GT labels to evaluate ({} without pose, {} "
                                     "without GT)",
                                     split_dir, sequence, s.skipped_no_pose, s.skipped_no_gt));
    s.result = ev.result();
    return s;
}
}  // namespace pndt::evalapp
