#include <fmt/format.h>

#include <chrono>

#include "segmenters.h"

namespace pndt::seg
{
void checkSegmentationInput(const SegmentationInput& in)
{
    if (!in.depth || in.depth->empty()) throw InputError(fmt::format("{}: the frame has no depth image", in.source));
    const auto& d = *in.depth;
    if (in.K.width != d.width || in.K.height != d.height)
        throw InputError(fmt::format("{}: depth image is {}x{} but the intrinsics are for {}x{}", in.source, d.width,
                                     d.height, in.K.width, in.K.height));
    if (in.color && !in.color->empty() && !in.color->sameSize(d.width, d.height))
        throw InputError(fmt::format("{}: colour image is {}x{} but the depth image is {}x{} (the front-end needs "
                                     "colour registered to depth)",
                                     in.source, in.color->width, in.color->height, d.width, d.height));
}

NetworkSegmenter::NetworkSegmenter(ModelDescription d, const ClassSet& classes)
    : d_(std::move(d)), net_(d_), post_(classes, mapModelClasses(d_, classes), d_.postprocess)
{
    const int C = int(d_.classes.size());
    if (d_.kind == "semantic")
        net_.checkOutputs({C});
    else
        net_.checkOutputs({C, 1, 2});
}

void NetworkSegmenter::segment(const SegmentationInput& in, PanopticFrame& frame)
{
    checkSegmentationInput(in);
    const auto& out = net_.run(in, timing_);
    const auto t0 = std::chrono::steady_clock::now();
    PanopticTensors t;
    t.classes = out[0].size[1];
    t.height = out[0].size[2];
    t.width = out[0].size[3];
    t.semantic = out[0].ptr<float>();
    if (d_.kind == "panoptic")
    {
        for (size_t i = 1; i < 3; ++i)
            if (out[i].size[2] != t.height || out[i].size[3] != t.width)
                throw InputError(fmt::format("{}: output '{}' is {}x{} but the semantic output is {}x{}", d_.onnx_path,
                                             d_.outputNames()[i], out[i].size[3], out[i].size[2], t.width, t.height));
        t.center = out[1].ptr<float>();
        t.offset = out[2].ptr<float>();
    }
    post_.run(t, small_);
    resizeLabels(small_, in.depth->width, in.depth->height, frame);
    timing_.postprocess_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::string NetworkSegmenter::describe() const
{
    return fmt::format("{} network '{}' ({}), {}x{} input, {} classes", d_.kind, d_.name, d_.onnx_path, d_.input_width,
                       d_.input_height, d_.classes.size());
}

}  // namespace pndt::seg
