// An ONNX network through OpenCV DNN (CPU), fed and read as a model description says:
// preprocessing of colour / depth into NCHW blobs, one forward pass, named outputs.
#pragma once

#include <pndt/seg/model_description.h>
#include <pndt/seg/segmenter.h>

#include <opencv2/dnn.hpp>

#include <vector>

namespace pndt::seg
{
class OnnxNetwork
{
   public:
    /// Loads d.onnx_path; throws InputError naming the file if it is missing or not a network
    /// OpenCV can read.
    explicit OnnxNetwork(const ModelDescription& d);

    /// Fills the input blobs from the frame (resized to the input size: colour bilinear, depth
    /// nearest) and runs the network; outputs in ModelDescription::outputNames() order.
    /// Throws InputError naming input.source when an input the model needs is missing.
    const std::vector<cv::Mat>& run(const SegmentationInput& input, SegmentationTiming& timing);

    /// Runs once on zero inputs and checks every output's shape: [1, channels[i], h, w] with
    /// channels[i] > 0 checked exactly. Throws InputError naming the file, the output and what
    /// was expected.
    void checkOutputs(const std::vector<int>& channels);

   private:
    void fillColor(const InputSpec& s, const SegmentationInput& in, cv::Mat& blob);
    void fillDepth(const InputSpec& s, const SegmentationInput& in, cv::Mat& blob);
    void forward();

    const ModelDescription& d_;
    cv::dnn::Net net_;
    std::vector<cv::Mat> blobs_;
    std::vector<cv::Mat> outputs_;
    cv::Mat resized_;  ///< scratch, reused
};

}  // namespace pndt::seg
