#include <fmt/format.h>

#include <chrono>

#include "segmenters.h"

namespace pndt::seg
{
namespace
{
/// The description's classes mapped onto the map's, an error naming the description file.
std::vector<uint16_t> classesOf(const ModelDescription& d, const ClassSet& classes)
{
    try
    {
        return mapDetectorClasses(d.classes, d.class_map, classes);
    }
    catch (const InputError& e)
    {
        throw InputError(fmt::format("{}: {}", d.path, e.what()));
    }
}
}  // namespace

DetectorSegmenter::DetectorSegmenter(ModelDescription d, const ClassSet& classes, const SegmenterOptions& options)
    : d_(std::move(d)),
      options_(options),
      net_(d_),
      classes_(classes),
      detector_to_class_(classesOf(d_, classes)),
      labeller_(classes, detector_to_class_, d_.geometry)
{
    net_.checkOutputs({int(d_.classes.size()), 4});
}

void DetectorSegmenter::segment(const SegmentationInput& in, PanopticFrame& frame)
{
    checkSegmentationInput(in);
    const auto& out = net_.run(in, timing_);
    const auto t0 = std::chrono::steady_clock::now();
    const cv::Mat& heat = out[0];
    const cv::Mat& box = out[1];
    if (heat.size[2] != box.size[2] || heat.size[3] != box.size[3])
        throw InputError(fmt::format("{}: heatmap is {}x{} but box_size is {}x{}", d_.onnx_path, heat.size[3],
                                     heat.size[2], box.size[3], box.size[2]));
    detections_ = decodeCenterNet(heat.ptr<float>(), heat.size[1], heat.size[2], heat.size[3], box.ptr<float>(),
                                  d_.input_width, d_.input_height, in.depth->width, in.depth->height, d_.detector);
    // Gravity in the camera frame: the world's up rotated into the camera, else the camera's −y.
    Eigen::Vector3d up_cam(0, -1, 0);
    if (options_.up_world && in.T_world_cam) up_cam = in.T_world_cam->linear().transpose() * *options_.up_world;
    labeller_.label(*in.depth, in.K, up_cam.normalized(), detections_, frame);
    timing_.postprocess_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::string DetectorSegmenter::detectionClassName(int c) const
{
    if (c < 0 || size_t(c) >= d_.classes.size()) return fmt::format("channel {}", c);
    const uint16_t id = detector_to_class_[size_t(c)];
    return d_.classes[size_t(c)] + " -> " + (id ? classes_.name(id) : std::string("ignored"));
}

std::string DetectorSegmenter::describe() const
{
    return fmt::format("detector + geometry, network '{}' ({}), {}x{} input, {} detector classes", d_.name,
                       d_.onnx_path, d_.input_width, d_.input_height, d_.classes.size());
}

}  // namespace pndt::seg
