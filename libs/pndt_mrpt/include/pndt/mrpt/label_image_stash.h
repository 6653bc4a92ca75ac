// The four label images of a PanopticFrame kept apart at their size. A frame converted
// from a new scan starts without labels (depthFrameFrom empties them); given these back
// before its labels are decoded or resized, it rewrites them in place instead of growing
// images from empty, which zero-fills every pixel first (~5 % of pndt-live's time).
#pragma once

#include <pndt/frame.h>

#include <utility>

namespace pndt
{
struct LabelImageStash
{
    Image<uint16_t> semantic;
    Image<float> semantic_score;
    Image<uint32_t> instance;
    Image<float> panoptic_score;

    /// Moves the frame's label images here; the frame is left without labels.
    void takeFrom(PanopticFrame& f)
    {
        semantic = std::exchange(f.semantic, {});
        semantic_score = std::exchange(f.semantic_score, {});
        instance = std::exchange(f.instance, {});
        panoptic_score = std::exchange(f.panoptic_score, {});
    }
    /// Hands them to a frame without labels (whose empty images stay here); a frame
    /// that has labels keeps its own.
    void giveTo(PanopticFrame& f)
    {
        if (f.hasLabels() || semantic.empty()) return;
        std::swap(f.semantic, semantic);
        std::swap(f.semantic_score, semantic_score);
        std::swap(f.instance, instance);
        std::swap(f.panoptic_score, panoptic_score);
    }
};
}  // namespace pndt
