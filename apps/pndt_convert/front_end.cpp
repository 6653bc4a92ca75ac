#include "front_end.h"

#include <fmt/format.h>

#include <set>

namespace pndt::convert
{

FrontEnd::FrontEnd(const std::string& model_description, const std::string& up_world, ConvertReport& report)
    : classes_(ClassSet::nyuv2_40()), report_(report)
{
    seg::SegmenterOptions so;
    if (!up_world.empty()) so.up_world = parseUpDirection(up_world);
    segmenter_ = seg::loadSegmenter(model_description, classes_, so);
    report_.segmenter = segmenter_->describe();
}

void FrontEnd::label(PanopticFrame& frame, const Image<seg::RgbPixel>* color, const Pose& T_world_cam)
{
    seg::SegmentationInput in;
    in.depth = &frame.depth;
    in.color = color;
    in.K = frame.K;
    in.T_world_cam = T_world_cam;
    in.source = frame.source;
    segmenter_->segment(in, frame);
    const auto& t = segmenter_->lastTiming();
    ++report_.frames_segmented;
    report_.segment_preprocess_ms += t.preprocess_ms;
    report_.segment_network_ms += t.network_ms;
    report_.segment_postprocess_ms += t.postprocess_ms;
    if (const auto* dets = segmenter_->lastDetections())
        for (const auto& d : *dets) ++report_.detections_per_class[segmenter_->detectionClassName(d.model_class)];
    // Instances of this frame per class (an instance's pixels share one class after Eq. 1).
    std::set<uint32_t> seen;
    for (size_t i = 0; i < frame.instance.data.size(); ++i)
        if (const uint32_t z = frame.instance.data[i]; z && seen.insert(z).second)
            ++report_.instances_per_class[classes_.name(frame.semantic.data[i])];
}

}  // namespace pndt::convert
