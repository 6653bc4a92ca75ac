// A frame as the update stages read it: contiguous rows, depth in float metres
// along z. Built from a FrameView, pointing at the caller's buffers where they
// already have that form and at map-owned conversion buffers otherwise.
#pragma once

#include <pndt/frame.h>
#include <pndt/map_options.h>

#include <string_view>
#include <vector>

namespace pndt
{
/// Read-only pixels with the vector-like surface the stages use (data(), size(), []).
template <typename T>
struct FrameSpan
{
    const T* ptr = nullptr;
    size_t n = 0;
    const T* data() const { return ptr; }
    size_t size() const { return n; }
    const T& operator[](size_t i) const { return ptr[i]; }
    bool empty() const { return n == 0; }
};

template <typename T>
struct FrameImage
{
    int width = 0;
    int height = 0;
    FrameSpan<T> data;
    bool empty() const { return data.empty(); }
    bool sameSize(int w, int h) const { return width == w && height == h; }
};

struct FramePixels
{
    CameraIntrinsics K;
    FrameImage<float> depth;  ///< metres along z; beyond a ray max_range: a value above max_range
    FrameImage<uint16_t> semantic;
    FrameImage<float> semantic_score;
    FrameImage<uint32_t> instance;
    FrameImage<float> panoptic_score;
    std::string_view source;

    bool hasLabels() const { return !semantic.empty(); }
    bool hasInstances() const { return !instance.empty(); }
    std::string where() const { return source.empty() ? std::string("frame") : std::string(source); }
};

/// Conversion buffers, kept between frames (they only grow).
struct FrameInputBuffers
{
    std::vector<float> depth;
    std::vector<uint16_t> semantic;
    std::vector<float> semantic_score;
    std::vector<uint32_t> instance;
    std::vector<float> panoptic_score;
};

/// Checks the view (intrinsics, sizes, strides, scale; InputError naming the
/// source) and gives its pixels in stage form, converting only what must be.
FramePixels resolveFrame(const FrameView& view, const MapOptions& options, FrameInputBuffers& buffers);
}  // namespace pndt
