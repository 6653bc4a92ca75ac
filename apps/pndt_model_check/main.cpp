// pndt-model-check: is a converted network right, and what does it see?
//   --write-input IMAGE DIR   the NCHW float32 blob the front-end feeds the network for IMAGE
//                             (DIR/input.npy), for a reference implementation to run on;
//   --check-reference DIR     OpenCV DNN on DIR/input.npy against DIR/<output>.npy (written by
//                             the reference): max abs difference per output, exit 1 above --tolerance;
//   --recording FOLDER        the front-end on frames of a Redwood / TUM folder (--frames, --every):
//                             detections (detector mode) and instances per class, per frame.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <opencv2/dnn.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <pndt/data/npz_writer.h>
#include <pndt/io/images.h>
#include <pndt/io/npz.h>
#include <pndt/io/sequence.h>
#include <pndt/seg/model_description.h>
#include <pndt/seg/segmenter.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

using namespace pndt;
namespace fs = std::filesystem;

namespace
{
void writeInput(const seg::ModelDescription& d, const std::string& image, const std::string& dir)
{
    if (d.inputs.size() != 1 || d.inputs[0].kind == "depth")
        throw InputError(d.path + ": --write-input handles single colour-input models only");
    const auto& s = d.inputs[0];
    const io::RgbImage rgb = io::readColorImage(image);
    const cv::Mat m(rgb.height, rgb.width, CV_8UC3, const_cast<seg::RgbPixel*>(rgb.data.data()));
    cv::Mat resized;
    cv::resize(m, resized, {d.input_width, d.input_height}, 0, 0, cv::INTER_LINEAR);  // as the front-end
    const size_t plane = size_t(d.input_width) * d.input_height;
    std::vector<float> blob(3 * plane);
    for (int ch = 0; ch < 3; ++ch)
    {
        const int src = s.kind == "bgr" ? 2 - ch : ch;
        for (size_t i = 0; i < plane; ++i)
            blob[ch * plane + i] = (s.scale * float(resized.data[3 * i + src]) - s.mean[ch]) / s.std[ch];
    }
    fs::create_directories(dir);
    std::ofstream(fs::path(dir) / "input.npy", std::ios::binary)
        << data::npyFloat32Bytes({1, 3, size_t(d.input_height), size_t(d.input_width)}, blob);
    fmt::print("pndt-model-check: wrote {}/input.npy ({}x{} from {})\n", dir, d.input_width, d.input_height, image);
}

int checkReference(const seg::ModelDescription& d, const std::string& dir, double tolerance)
{
    const io::NpyArray in = io::readNpyFile((fs::path(dir) / "input.npy").string());
    std::vector<int> shape(in.shape.begin(), in.shape.end());
    cv::Mat blob(int(shape.size()), shape.data(), CV_32F, const_cast<float*>(in.data.data()));
    cv::dnn::Net net = cv::dnn::readNetFromONNX(d.onnx_path);
    net.setInput(blob, d.inputs.at(0).name);
    std::vector<cv::Mat> outs;
    const auto names = d.outputNames();
    net.forward(outs, names);
    int bad = 0;
    for (size_t k = 0; k < names.size(); ++k)
    {
        const io::NpyArray ref = io::readNpyFile((fs::path(dir) / (names[k] + ".npy")).string());
        const cv::Mat& o = outs[k];
        if (size_t(o.total()) != ref.data.size())
            throw InputError(fmt::format("{}: output '{}' has {} values, the reference {}", d.onnx_path, names[k],
                                         o.total(), ref.data.size()));
        double max_diff = 0, max_ref = 0;
        const float* p = o.ptr<float>();
        for (size_t i = 0; i < ref.data.size(); ++i)
        {
            max_diff = std::max(max_diff, double(std::abs(p[i] - ref.data[i])));
            max_ref = std::max(max_ref, double(std::abs(ref.data[i])));
        }
        const bool ok = max_diff <= tolerance * std::max(1.0, max_ref);
        bad += ok ? 0 : 1;
        fmt::print("pndt-model-check: {:<10} max |OpenCV - reference| = {:.3g} (values up to {:.3g}): {}\n",
                   names[k], max_diff, max_ref, ok ? "ok" : "MISMATCH");
    }
    return bad ? 1 : 0;
}

/// Colour frame with the detector's boxes | the label images over it (class colour, instance
/// outlines in the instance colour), written atomically as DIR/frame_<id>.png.
void writePicture(const std::string& dir, const io::RgbdFrame& f, const PanopticFrame& labels,
                  const seg::Segmenter& seg, const ClassSet& classes, double scale)
{
    const int W = f.color.width, H = f.color.height;
    cv::Mat rgb(H, W, CV_8UC3, const_cast<seg::RgbPixel*>(f.color.data.data()));
    cv::Mat left, right;
    cv::cvtColor(rgb, left, cv::COLOR_RGB2BGR);
    right = left.clone();
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
        {
            const uint16_t c = labels.semantic.at(y, x);
            if (!c) continue;
            const Rgb k = classColor(c);
            auto& px = right.at<cv::Vec3b>(y, x);
            px = cv::Vec3b(uchar((px[0] + 2 * k.b) / 3), uchar((px[1] + 2 * k.g) / 3), uchar((px[2] + 2 * k.r) / 3));
            const uint32_t z = labels.hasInstances() ? labels.instance.at(y, x) : 0;
            const bool edge = z && (x == 0 || y == 0 || x == W - 1 || y == H - 1 || labels.instance.at(y, x - 1) != z ||
                                    labels.instance.at(y - 1, x) != z || labels.instance.at(y, x + 1) != z ||
                                    labels.instance.at(y + 1, x) != z);
            if (edge) px = cv::Vec3b(255, 255, 255);
        }
    if (const auto* ds = seg.lastDetections())
        for (const auto& d : *ds)
        {
            cv::rectangle(left, cv::Point(int(d.x0), int(d.y0)), cv::Point(int(d.x1) - 1, int(d.y1) - 1),
                          cv::Scalar(0, 255, 255), 2);
            cv::putText(left, fmt::format("{} {:.2f}", seg.detectionClassName(d.model_class), d.score),
                        cv::Point(int(d.x0) + 3, std::max(14, int(d.y0) + 16)), cv::FONT_HERSHEY_SIMPLEX, 0.5,
                        cv::Scalar(0, 255, 255), 1, cv::LINE_AA);
        }
    // Legend of the classes present.
    std::set<uint16_t> present(labels.semantic.data.begin(), labels.semantic.data.end());
    int row = 0;
    for (uint16_t c : present)
    {
        if (!c) continue;
        const Rgb k = classColor(c);
        cv::rectangle(right, cv::Rect(8, 8 + 20 * row, 14, 14), cv::Scalar(k.b, k.g, k.r), cv::FILLED);
        cv::putText(right, classes.name(c), cv::Point(28, 20 + 20 * row), cv::FONT_HERSHEY_SIMPLEX, 0.5,
                    cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
        ++row;
    }
    cv::Mat both;
    cv::hconcat(left, right, both);
    if (scale != 1.0) cv::resize(both, both, {}, scale, scale, cv::INTER_AREA);
    fs::create_directories(dir);
    const std::string path = (fs::path(dir) / ("frame_" + f.id + ".png")).string();
    const std::string tmp = path + ".tmp.png";
    if (!cv::imwrite(tmp, both)) throw std::runtime_error("cannot write " + tmp);
    fs::rename(tmp, path);
}

void describeRecording(const std::string& model, const std::string& folder, int frames, int every,
                       const std::string& up, const std::string& pictures, double scale)
{
    const ClassSet classes = ClassSet::nyuv2_40();
    seg::SegmenterOptions so;
    if (!up.empty())
    {
        std::istringstream in(up);
        Eigen::Vector3d u;
        std::string extra;
        if (!(in >> u.x() >> u.y() >> u.z()) || (in >> extra) || !u.allFinite() || u.norm() == 0)
            throw InputError(fmt::format("--up must be \"x y z\", three finite numbers not all 0 (got \"{}\")", up));
        so.up_world = u.normalized();
    }
    auto seg = seg::loadSegmenter(model, classes, so);
    const io::RgbdSequence seq = io::openRecordingFolder(folder);
    PanopticFrame out;
    for (size_t i = 0, n = 0; i < seq.size() && int(n) < frames; i += size_t(every), ++n)
    {
        const io::RgbdFrame f = seq.load(i);
        seg::SegmentationInput in;
        in.depth = &f.depth;
        in.color = f.color.empty() ? nullptr : &f.color;
        in.K = f.K;
        in.T_world_cam = f.T_world_cam;
        in.source = f.id;
        seg->segment(in, out);
        std::string dets;
        if (const auto* ds = seg->lastDetections())
            for (const auto& d : *ds)
                dets += fmt::format("  {} {:.2f} [{:.0f},{:.0f},{:.0f},{:.0f}]", seg->detectionClassName(d.model_class),
                                    d.score, d.x0, d.y0, d.x1, d.y1);
        std::map<std::string, int> inst;
        std::set<uint32_t> seen;
        size_t stuff = 0;
        for (size_t p = 0; p < out.semantic.data.size(); ++p)
        {
            if (!out.instance.empty() && out.instance.data[p] && seen.insert(out.instance.data[p]).second)
                ++inst[classes.name(out.semantic.data[p])];
            if (out.semantic.data[p] && !classes.isThing(out.semantic.data[p])) ++stuff;
        }
        if (!pictures.empty() && !f.color.empty()) writePicture(pictures, f, out, *seg, classes, scale);
        std::string is;
        for (const auto& [c, k] : inst) is += fmt::format(" {} {}", k, c);
        fmt::print("frame {}: {:.0f} ms; stuff {:.0f}% of pixels; instances:{}\n  detections:{}\n", f.id,
                   seg->lastTiming().total(), 100.0 * double(stuff) / double(out.semantic.data.size()),
                   is.empty() ? " none" : is, dets.empty() ? " none" : dets);
    }
}
}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"pndt-model-check: check a converted segmentation network and show what it sees"};
    std::string model, write_image, dir, recording, up, pictures;
    double tolerance = 1e-3, picture_scale = 1.0;
    int frames = 5, every = 50;
    app.add_option("--model", model, "model description (JSON)")->required();
    app.add_option("--write-input", write_image, "colour image whose network input blob to write to --dir");
    app.add_option("--check-reference", dir, "folder with input.npy and the reference outputs <name>.npy");
    app.add_option("--dir", dir, "folder for --write-input");
    app.add_option("--tolerance", tolerance, "max abs difference, relative to max(1, largest value)")
        ->capture_default_str();
    app.add_option("--recording", recording, "Redwood / TUM folder to run the front-end on");
    app.add_option("--frames", frames, "frames of --recording")->capture_default_str()->check(CLI::Range(1, 1000000));
    app.add_option("--every", every, "use every n-th frame")->capture_default_str()->check(CLI::Range(1, 1000000));
    app.add_option("--up", up, "gravity up \"x y z\" in the recording's world frame");
    app.add_option("--pictures", pictures, "write each frame's boxes and label images as PNGs into this folder");
    app.add_option("--picture-scale", picture_scale, "scale of the pictures")->check(CLI::Range(0.05, 4.0));
    CLI11_PARSE(app, argc, argv);
    try
    {
        const seg::ModelDescription d = seg::loadModelDescription(model);
        if (!write_image.empty())
        {
            if (dir.empty()) throw InputError("--write-input needs --dir");
            writeInput(d, write_image, dir);
            return 0;
        }
        int rc = 0;
        if (!dir.empty()) rc = checkReference(d, dir, tolerance);
        if (!recording.empty())
            describeRecording(model, recording, frames, every, up, pictures, picture_scale);
        else
        {
            // The description alone says nothing of the network: load it as the front-end
            // does (its inputs, outputs and classes checked, one run on a blank input).
            const ClassSet classes = ClassSet::nyuv2_40();
            const auto seg = seg::loadSegmenter(model, classes);
            fmt::print("{}: {}; the network loads, has the inputs and outputs the description names and runs on a "
                       "blank input\n",
                       model, seg->describe());
        }
        return rc;
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-model-check: error: {}\n", e.what());
        return 1;
    }
}
