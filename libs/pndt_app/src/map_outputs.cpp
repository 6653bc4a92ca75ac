#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <pndt/app/map_outputs.h>
#include <pndt/app/map_pictures.h>
#include <pndt/io/atomic_file.h>
#include <pndt/mrpt/map_files.h>

#include <fstream>
#include <map>

namespace pndt::app
{
namespace
{
nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
}  // namespace

void writeInstanceReport(const PanopticMap& map, const std::string& path)
{
    std::map<std::string, nlohmann::json> by_class;
    const auto instances = map.instances();
    for (const MapInstance& mi : instances)
        by_class[map.options().classes.name(mi.semantic)].push_back({{"id", mi.id},
                                                                     {"class_id", mi.semantic},
                                                                     {"voxels", mi.voxel_count},
                                                                     {"centroid", vec(mi.centroid)},
                                                                     {"extent", vec(mi.bbox_max - mi.bbox_min)},
                                                                     {"bbox_min", vec(mi.bbox_min)},
                                                                     {"bbox_max", vec(mi.bbox_max)}});
    nlohmann::json j;
    j["voxel_size"] = map.options().voxel_size;
    j["instances"] = instances.size();
    j["classes"] = nlohmann::json::object();
    for (auto& [name, list] : by_class) j["classes"][name] = list;
    io::writeFileAtomically(path, [&](const std::string& tmp) {
        std::ofstream f(tmp);
        f << j.dump(2) << "\n";
        io::closeWrittenStream(f, path);
    });
}

void writeRenderedViews(const PanopticMap& map, const Pose& T, const CameraIntrinsics& K, const std::string& prefix)
{
    RenderedView v;
    map.render(T, K, v);
    cv::Mat sem(K.height, K.width, CV_8UC3, cv::Scalar(0, 0, 0)), inst = sem.clone(), pan = sem.clone(),
        rgb8 = sem.clone();
    cv::Mat label(K.height, K.width, CV_8UC1, cv::Scalar(0)), depth(K.height, K.width, CV_16UC1, cv::Scalar(0));
    const auto bgr = [](Rgb c) { return cv::Vec3b(c.b, c.g, c.r); };
    const ClassSet& classes = map.options().classes;
    std::vector<uint64_t> semantic_pixels(classes.size(), 0), panoptic_pixels(classes.size(), 0);
    for (int r = 0; r < K.height; ++r)
        for (int c = 0; c < K.width; ++c)
        {
            const size_t i = size_t(r) * K.width + c;
            if (!(v.depth.data[i] > 0)) continue;
            const uint32_t z = v.instance.data[i];
            const uint16_t ps = v.panoptic_semantic.data[i];
            sem.at<cv::Vec3b>(r, c) = bgr(classColor(v.semantic.data[i]));
            if (v.semantic.data[i] < classes.size()) ++semantic_pixels[v.semantic.data[i]];
            if (ps < classes.size()) ++panoptic_pixels[ps];
            inst.at<cv::Vec3b>(r, c) = bgr(instanceColor(z));
            pan.at<cv::Vec3b>(r, c) = bgr(z ? instanceColor(z) : classColor(ps));
            // R = class, G<<8|B = instance (stored BGR).
            rgb8.at<cv::Vec3b>(r, c) = cv::Vec3b(uint8_t(z & 0xFF), uint8_t((z >> 8) & 0xFF), uint8_t(ps));
            label.at<uint8_t>(r, c) = uint8_t(v.semantic.data[i]);
            depth.at<uint16_t>(r, c) = uint16_t(std::min(65535.f, v.depth.data[i] * 1000.f));
        }
    // The colour views carry a legend; the encodings stay the image alone.
    writePngFile(withLegend(sem, classLegend(semantic_pixels, classes)), prefix + "_semantic.png");
    writePngFile(inst, prefix + "_instance.png");
    // Panoptic: stuff in its class colour, things in one colour per instance.
    bool things = false;
    for (size_t c = 0; c < panoptic_pixels.size(); ++c)
        if (classes.isThing(uint32_t(c)) && panoptic_pixels[c] > 0)
        {
            things = true;
            panoptic_pixels[c] = 0;
        }
    std::vector<LegendEntry> pan_legend = classLegend(panoptic_pixels, classes);
    if (things) pan_legend.push_back({Rgb{160, 160, 160}, "things: 1 colour each"});
    writePngFile(withLegend(pan, pan_legend), prefix + "_panoptic.png");
    writePngFile(rgb8, prefix + "_panoptic_rgb8.png");
    writePngFile(label, prefix + "_semantic_label.png");
    writePngFile(depth, prefix + "_depth.png");
}

void writeFloorPlan(const PanopticMap& map, const std::string& path) { writePngFile(floorPlan(map), path); }

}  // namespace pndt::app
