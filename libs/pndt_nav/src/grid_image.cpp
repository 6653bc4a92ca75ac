// Drawing the grid, objects, goal and path (grid_image.h).
#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <pndt/class_set.h>
#include <pndt/io/atomic_file.h>
#include <pndt/nav/grid_image.h>

#include <cmath>
#include <stdexcept>

namespace pndt::nav
{
void writeGridPicture(const GridPicture& p, const std::string& png_path)
{
    const auto& g = p.grid->grid;
    const int nx = int(g.getSizeX()), ny = int(g.getSizeY()), s = std::max(1, p.scale);
    cv::Mat3b img(ny * s, nx * s);
    for (int cy = 0; cy < ny; ++cy)
        for (int cx = 0; cx < nx; ++cx)
        {
            const CellState st = cellState(g, cx, cy);
            const cv::Vec3b c = st == CellState::Free ? cv::Vec3b(255, 255, 255)
                                : st == CellState::Occupied ? cv::Vec3b(0, 0, 0)
                                                            : cv::Vec3b(160, 160, 160);
            img(cv::Rect(cx * s, (ny - 1 - cy) * s, s, s)).setTo(c);
        }
    const double res = g.getResolution();
    auto px = [&](const Eigen::Vector2d& w) {
        return cv::Point(int(std::lround((w.x() - g.getXMin()) / res * s)),
                         int(std::lround((ny * s) - (w.y() - g.getYMin()) / res * s)));
    };
    if (p.objects)
        for (const MapObject& o : *p.objects)
        {
            const Rgb rgb = classColor(o.class_id);
            const cv::Scalar col(rgb.b, rgb.g, rgb.r);
            const auto c = o.footprint.corners();
            std::vector<cv::Point> poly;
            for (const auto& k : c) poly.push_back(px(k));
            cv::polylines(img, poly, true, col, o.id == p.highlight_id ? 3 : 1, cv::LINE_AA);
            // Dark text on a white halo stays readable over any cell.
            const std::string label = fmt::format("{} {}", o.class_name, o.id);
            const cv::Point at = px(o.footprint.center) + cv::Point(-int(label.size()) * 3, 4);
            cv::putText(img, label, at, cv::FONT_HERSHEY_SIMPLEX, 0.35, cv::Scalar(255, 255, 255), 3, cv::LINE_AA);
            cv::putText(img, label, at, cv::FONT_HERSHEY_SIMPLEX, 0.35, col * 0.6, 1, cv::LINE_AA);
        }
    if (p.path && p.path->found)
        for (size_t i = 1; i < p.path->points.size(); ++i)
            cv::line(img, px({p.path->points[i - 1].x, p.path->points[i - 1].y}),
                     px({p.path->points[i].x, p.path->points[i].y}), cv::Scalar(255, 120, 0), 2, cv::LINE_AA);
    for (size_t i = 0; i < p.trajectory.size(); i += 2)
        cv::circle(img, px(p.trajectory[i]), 1, cv::Scalar(0, 160, 0), cv::FILLED);
    if (p.goal && p.goal->found)
    {
        const Eigen::Vector2d at(p.goal->x, p.goal->y);
        const Eigen::Vector2d tip = at + 0.4 * Eigen::Vector2d(std::cos(p.goal->yaw), std::sin(p.goal->yaw));
        cv::circle(img, px(at), int(0.3 / res * s), cv::Scalar(0, 0, 255), 2, cv::LINE_AA);
        cv::arrowedLine(img, px(at), px(tip), cv::Scalar(0, 0, 255), 2, cv::LINE_AA);
    }
    // Encoded first, then written whole under a temporary name and renamed: a consumer that
    // follows the answers (--watch) never reads half a picture; a failed write is an error.
    std::vector<uint8_t> png;
    if (!cv::imencode(".png", img, png)) throw std::runtime_error(fmt::format("{}: cannot encode the PNG", png_path));
    io::writeFileAtomically(png_path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

}  // namespace pndt::nav
