#include "onnx_network.h"

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include <chrono>
#include <filesystem>

namespace pndt::seg
{
namespace
{
double msSince(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::string shapeText(const cv::Mat& m)
{
    std::string s = "[";
    for (int i = 0; i < m.dims; ++i) s += (i ? ", " : "") + std::to_string(m.size[i]);
    return s + "]";
}
}  // namespace

OnnxNetwork::OnnxNetwork(const ModelDescription& d) : d_(d)
{
    if (!std::filesystem::is_regular_file(d.onnx_path))
        throw InputError(fmt::format("{}: the network file {} (key 'onnx') does not exist", d.path, d.onnx_path));
    try
    {
        net_ = cv::dnn::readNetFromONNX(d.onnx_path);
    }
    catch (const cv::Exception& e)
    {
        throw InputError(fmt::format("{}: OpenCV DNN cannot read it as an ONNX network: {}", d.onnx_path, e.err));
    }
    if (net_.empty()) throw InputError(fmt::format("{}: OpenCV DNN read an empty network", d.onnx_path));
    net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
    for (const auto& s : d.inputs)
    {
        const int shape[] = {1, s.channels(), d.input_height, d.input_width};
        blobs_.emplace_back(4, shape, CV_32F, cv::Scalar(0));
    }
}

void OnnxNetwork::forward()
{
    for (size_t i = 0; i < blobs_.size(); ++i) net_.setInput(blobs_[i], d_.inputs[i].name);
    net_.forward(outputs_, d_.outputNames());
}

void OnnxNetwork::checkOutputs(const std::vector<int>& channels)
{
    const auto names = d_.outputNames();
    std::string expected;
    for (size_t i = 0; i < names.size(); ++i)
        expected += fmt::format("{}'{}' [1, {}, h, w]", i ? ", " : "", names[i],
                                channels[i] > 0 ? std::to_string(channels[i]) : std::string("C"));
    std::string inputs;
    for (const InputSpec& in : d_.inputs) inputs += fmt::format("{}'{}'", inputs.empty() ? "" : ", ", in.name);
    try
    {
        for (auto& b : blobs_) b.setTo(0);
        forward();
    }
    catch (const cv::Exception& e)
    {
        throw InputError(fmt::format("{}: running the network on a blank {}x{} input failed (the description {} "
                                     "feeds inputs {} and expects outputs {}; a network input it does not feed "
                                     "shows here as an OpenCV assertion): {}",
                                     d_.onnx_path, d_.input_width, d_.input_height, d_.path, inputs, expected, e.err));
    }
    for (size_t i = 0; i < names.size(); ++i)
    {
        const cv::Mat& m = outputs_.at(i);
        const bool ok = m.dims == 4 && m.size[0] == 1 && m.type() == CV_32F &&
                        (channels[i] <= 0 || m.size[1] == channels[i]) && m.size[2] > 0 && m.size[3] > 0;
        if (!ok)
            throw InputError(fmt::format("{}: output '{}' has shape {} but the description {} expects {}",
                                         d_.onnx_path, names[i], shapeText(m), d_.path, expected));
    }
}

void OnnxNetwork::fillColor(const InputSpec& s, const SegmentationInput& in, cv::Mat& blob)
{
    if (!in.color || in.color->empty())
        throw InputError(fmt::format("{}: the model {} needs a colour image (input '{}') but the frame has none",
                                     in.source, d_.path, s.name));
    const auto& c = *in.color;
    const cv::Mat rgb(c.height, c.width, CV_8UC3, const_cast<RgbPixel*>(c.data.data()));
    cv::resize(rgb, resized_, {d_.input_width, d_.input_height}, 0, 0, cv::INTER_LINEAR);
    const size_t plane = size_t(d_.input_width) * d_.input_height;
    float* out = blob.ptr<float>();
    for (int ch = 0; ch < 3; ++ch)
    {
        const int src_ch = s.kind == "bgr" ? 2 - ch : ch;
        const float a = s.scale / s.std[ch], b = -s.mean[ch] / s.std[ch];
        float* o = out + ch * plane;
        const uint8_t* p = resized_.ptr<uint8_t>();
        for (size_t i = 0; i < plane; ++i) o[i] = a * float(p[3 * i + src_ch]) + b;
    }
}

void OnnxNetwork::fillDepth(const InputSpec& s, const SegmentationInput& in, cv::Mat& blob)
{
    const auto& d = *in.depth;
    const cv::Mat depth(d.height, d.width, CV_32F, const_cast<float*>(d.data.data()));
    cv::resize(depth, resized_, {d_.input_width, d_.input_height}, 0, 0, cv::INTER_NEAREST);
    const size_t plane = size_t(d_.input_width) * d_.input_height;
    const float a = s.scale / s.std[0], b = -s.mean[0] / s.std[0];
    float* o = blob.ptr<float>();
    const float* p = resized_.ptr<float>();
    for (size_t i = 0; i < plane; ++i) o[i] = std::isfinite(p[i]) && p[i] > 0 ? a * p[i] + b : b;
}

const std::vector<cv::Mat>& OnnxNetwork::run(const SegmentationInput& in, SegmentationTiming& timing)
{
    auto t0 = std::chrono::steady_clock::now();
    for (size_t i = 0; i < blobs_.size(); ++i)
    {
        if (d_.inputs[i].kind == "depth")
            fillDepth(d_.inputs[i], in, blobs_[i]);
        else
            fillColor(d_.inputs[i], in, blobs_[i]);
    }
    timing.preprocess_ms = msSince(t0);
    t0 = std::chrono::steady_clock::now();
    try
    {
        forward();
    }
    catch (const cv::Exception& e)
    {
        throw std::runtime_error(fmt::format("{}: {}: the network failed: {}", in.source, d_.onnx_path, e.err));
    }
    timing.network_ms = msSince(t0);
    return outputs_;
}

}  // namespace pndt::seg
