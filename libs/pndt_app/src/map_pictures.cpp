#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <pndt/app/map_pictures.h>
#include <pndt/io/atomic_file.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <numeric>

namespace pndt::app
{
namespace
{
cv::Scalar bgr(Rgb c) { return cv::Scalar(c.b, c.g, c.r); }
}  // namespace

std::vector<LegendEntry> classLegend(const std::vector<uint64_t>& pixels_per_class, const ClassSet& classes,
                                     size_t max_entries)
{
    std::vector<uint16_t> ids;
    for (size_t c = 1; c < pixels_per_class.size() && c < classes.size(); ++c)
        if (pixels_per_class[c] > 0) ids.push_back(uint16_t(c));
    std::stable_sort(ids.begin(), ids.end(),
                     [&](uint16_t a, uint16_t b) { return pixels_per_class[a] > pixels_per_class[b]; });
    if (ids.size() > max_entries) ids.resize(max_entries);
    std::vector<LegendEntry> out;
    for (uint16_t c : ids) out.push_back({classColor(c), classes.name(c)});
    return out;
}

cv::Mat withLegend(const cv::Mat& image, const std::vector<LegendEntry>& entries)
{
    constexpr int kRow = 22, kPanel = 190;
    const int rows = std::max(image.rows, 12 + kRow * int(entries.size()));
    cv::Mat out(rows, image.cols + kPanel, CV_8UC3, cv::Scalar(255, 255, 255));
    image.copyTo(out(cv::Rect(0, 0, image.cols, image.rows)));
    for (size_t k = 0; k < entries.size(); ++k)
    {
        const int y = 8 + kRow * int(k);
        const cv::Rect swatch(image.cols + 10, y, 16, 16);
        cv::rectangle(out, swatch, bgr(entries[k].color), cv::FILLED);
        cv::rectangle(out, swatch, cv::Scalar(0, 0, 0), 1);
        cv::putText(out, entries[k].text, {image.cols + 34, y + 13}, cv::FONT_HERSHEY_SIMPLEX, 0.45,
                    cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
    return out;
}

cv::Mat floorPlan(const PanopticMap& map, int pixels_per_voxel)
{
    map.finalize();
    const auto& store = map.voxels();
    const ClassSet& classes = map.options().classes;
    const int ceiling = classes.find("ceiling");
    // Per x-y cell: the highest occupied voxel that is not ceiling.
    struct Top
    {
        int32_t z = std::numeric_limits<int32_t>::min();
        uint32_t voxel = kNoRecord;
    };
    std::map<std::pair<int32_t, int32_t>, Top> top;
    int32_t x0 = std::numeric_limits<int32_t>::max(), y0 = x0, x1 = std::numeric_limits<int32_t>::min(), y1 = x1;
    for (uint32_t i = 0; i < store.size(); ++i)
    {
        if (!map.isOccupied(store[i])) continue;
        const PanopticLabel l = map.panopticLabel(i);
        if (ceiling >= 0 && l.semantic == ceiling) continue;
        const VoxelKey k = store.key(i);
        Top& t = top[{k.x, k.y}];
        if (k.z > t.z) t = {k.z, i};
        x0 = std::min(x0, k.x);
        x1 = std::max(x1, k.x);
        y0 = std::min(y0, k.y);
        y1 = std::max(y1, k.y);
    }
    if (top.empty()) return cv::Mat(64, 64, CV_8UC3, cv::Scalar(255, 255, 255));
    const int s = std::max(1, pixels_per_voxel), margin = 40;
    const int W = (x1 - x0 + 1) * s + 2 * margin, H = (y1 - y0 + 1) * s + 2 * margin;
    cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
    // Image rows grow downwards, world y upwards.
    const auto cellRect = [&](int32_t x, int32_t y) { return cv::Rect(margin + (x - x0) * s, margin + (y1 - y) * s, s, s); };
    std::vector<uint64_t> cells_per_class(classes.size(), 0);
    std::map<uint32_t, cv::Mat> instance_mask;
    std::map<uint32_t, uint16_t> instance_class;
    for (const auto& [xy, t] : top)
    {
        const PanopticLabel l = map.panopticLabel(t.voxel);
        const uint16_t cls = l.semantic ? l.semantic : map.semanticLabel(t.voxel);
        cv::rectangle(img, cellRect(xy.first, xy.second), cls ? bgr(classColor(cls)) : cv::Scalar(200, 200, 200),
                      cv::FILLED);
        if (cls < cells_per_class.size()) ++cells_per_class[cls];
        if (l.instance)
        {
            cv::Mat& m = instance_mask[l.instance];
            if (m.empty()) m = cv::Mat::zeros(H, W, CV_8UC1);
            cv::rectangle(m, cellRect(xy.first, xy.second), cv::Scalar(255), cv::FILLED);
            instance_class[l.instance] = l.semantic;
        }
    }
    // Outlines and names of the instances seen from above.
    for (const auto& [id, m] : instance_mask)
    {
        std::vector<std::vector<cv::Point>> contours;
        cv::findContours(m, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
        cv::drawContours(img, contours, -1, cv::Scalar(0, 0, 0), 2, cv::LINE_AA);
        const cv::Moments mo = cv::moments(m, true);
        if (mo.m00 <= 0) continue;
        const std::string text = fmt::format("{} {}", classes.name(instance_class[id]), id);
        const cv::Point at(int(mo.m10 / mo.m00) - 4 * int(text.size()), int(mo.m01 / mo.m00) + 4);
        cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(255, 255, 255), 3, cv::LINE_AA);
        cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
    // Scale bar: 1 m.
    const int bar = int(std::lround(s / map.options().voxel_size));
    cv::line(img, {margin, H - 15}, {margin + bar, H - 15}, cv::Scalar(0, 0, 0), 3);
    cv::putText(img, "1 m", {margin + bar + 8, H - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    return withLegend(img, classLegend(cells_per_class, classes));
}

void writePngFile(const cv::Mat& image, const std::string& path)
{
    io::writeFileAtomically(path, [&](const std::string& tmp) {
        std::vector<uchar> png;
        if (!cv::imencode(".png", image, png)) throw std::runtime_error("PNG encoding failed for " + path);
        std::ofstream f(tmp, std::ios::binary);
        f.write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
        io::closeWrittenStream(f, path);
    });
}

}  // namespace pndt::app
