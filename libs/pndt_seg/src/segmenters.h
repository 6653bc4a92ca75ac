// The Segmenter implementations behind loadSegmenter (internal).
#pragma once

#include <pndt/seg/detector_geometry.h>
#include <pndt/seg/model_description.h>
#include <pndt/seg/panoptic_postprocess.h>
#include <pndt/seg/segmenter.h>

#include <memory>

#include "onnx_network.h"

namespace pndt::seg
{
/// "panoptic" and "semantic" models: network → PanopticPostprocessor → labels resized to depth.
class NetworkSegmenter : public Segmenter
{
   public:
    NetworkSegmenter(ModelDescription d, const ClassSet& classes);
    void segment(const SegmentationInput& input, PanopticFrame& frame) override;
    std::string describe() const override;

   private:
    ModelDescription d_;
    OnnxNetwork net_;
    PanopticPostprocessor post_;
    PanopticFrame small_;  ///< labels at the network's output size
};

/// "detector" models: CenterNet boxes → DetectorGeometryLabeller (depth segments + planes).
class DetectorSegmenter : public Segmenter
{
   public:
    DetectorSegmenter(ModelDescription d, const ClassSet& classes, const SegmenterOptions& options);
    void segment(const SegmentationInput& input, PanopticFrame& frame) override;
    std::string describe() const override;
    const std::vector<Detection>* lastDetections() const override { return &detections_; }
    std::string detectionClassName(int model_class) const override;

   private:
    ModelDescription d_;
    SegmenterOptions options_;
    OnnxNetwork net_;
    const ClassSet& classes_;
    std::vector<uint16_t> detector_to_class_;
    DetectorGeometryLabeller labeller_;
    std::vector<Detection> detections_;
};

/// Checks the frame's images against each other (sizes, K); throws InputError naming the source.
void checkSegmentationInput(const SegmentationInput& in);

}  // namespace pndt::seg
