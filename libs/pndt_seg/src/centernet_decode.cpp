#include <fmt/format.h>
#include <pndt/seg/detector_geometry.h>

#include <algorithm>

namespace pndt::seg
{
std::vector<Detection> decodeCenterNet(const float* heatmap, int classes, int grid_h, int grid_w,
                                       const float* box_size, int input_w, int input_h, int image_w,
                                       int image_h, const CenterNetDecodeOptions& o)
{
    if (!heatmap || !box_size) throw InputError("decodeCenterNet: missing heatmap or box_size tensor");
    if (classes < 1 || grid_h < 1 || grid_w < 1 || input_w < 1 || input_h < 1 || image_w < 1 || image_h < 1)
        throw InputError(fmt::format("decodeCenterNet: bad sizes (classes {}, grid {}x{}, input {}x{}, image {}x{})",
                                     classes, grid_w, grid_h, input_w, input_h, image_w, image_h));
    if (o.stride < 1 || o.top_k < 1) throw InputError("decodeCenterNet: stride and top_k must be >= 1");

    const size_t plane = size_t(grid_h) * size_t(grid_w);
    const float sx = float(image_w) / float(input_w), sy = float(image_h) / float(input_h);
    std::vector<Detection> out;
    for (int c = 0; c < classes; ++c)
    {
        const float* h = heatmap + size_t(c) * plane;
        for (int y = 0; y < grid_h; ++y)
            for (int x = 0; x < grid_w; ++x)
            {
                const float v = h[size_t(y) * grid_w + x];
                if (!(v > o.score_threshold)) continue;
                // A peak is >= every 3x3 neighbour (plateaus keep their first cell only).
                bool peak = true;
                for (int dy = -1; dy <= 1 && peak; ++dy)
                    for (int dx = -1; dx <= 1 && peak; ++dx)
                    {
                        const int ny = y + dy, nx = x + dx;
                        if ((dy == 0 && dx == 0) || ny < 0 || nx < 0 || ny >= grid_h || nx >= grid_w) continue;
                        const float n = h[size_t(ny) * grid_w + nx];
                        const bool earlier = dy < 0 || (dy == 0 && dx < 0);
                        if (n > v || (earlier && n == v)) peak = false;
                    }
                if (!peak) continue;
                const size_t i = size_t(y) * grid_w + x;
                const float l = box_size[i] * o.box_scale, t = box_size[plane + i] * o.box_scale;
                const float r = box_size[2 * plane + i] * o.box_scale, b = box_size[3 * plane + i] * o.box_scale;
                const float cx = float(o.stride * x), cy = float(o.stride * y);
                Detection d;
                d.model_class = c;
                d.score = std::min(v, 1.f);
                d.x0 = std::clamp((cx - l) * sx, 0.f, float(image_w));
                d.y0 = std::clamp((cy - t) * sy, 0.f, float(image_h));
                d.x1 = std::clamp((cx + r) * sx, 0.f, float(image_w));
                d.y1 = std::clamp((cy + b) * sy, 0.f, float(image_h));
                if (d.x1 > d.x0 && d.y1 > d.y0) out.push_back(d);
            }
    }
    std::stable_sort(out.begin(), out.end(), [](const Detection& a, const Detection& b) { return a.score > b.score; });
    if (out.size() > size_t(o.top_k)) out.resize(size_t(o.top_k));
    return out;
}

}  // namespace pndt::seg
