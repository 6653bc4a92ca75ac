// RgbdSequence::load: decodes one indexed frame.
#include "text_util.h"

#include <pndt/io/npz.h>
#include <pndt/io/sequence.h>

#include <fmt/format.h>

#include <stdexcept>

namespace pndt::io
{
namespace
{
template <typename T>
void checkSize(const Image<T>& img, const CameraIntrinsics& K, const std::string& path,
               const char* what)
{
    if (K.width > 0 && K.height > 0 && !img.sameSize(K.width, K.height))
        detail::failFile(path, fmt::format("{} image is {} x {} but its intrinsics are for {} x {}",
                                           what, img.width, img.height, K.width, K.height));
}

/// A frame's instance labels go with its semantic ones pixel by pixel: the same size.
template <typename A, typename B>
void checkPair(const Image<A>& semantic, const std::string& semantic_path, const Image<B>& instance,
               const std::string& instance_path, const char* what)
{
    if (!semantic.empty() && !instance.empty() && !instance.sameSize(semantic.width, semantic.height))
        detail::failFile(instance_path, fmt::format("{} instance image is {} x {} but its semantic image ({}) is {} x {}",
                                                    what, instance.width, instance.height, semantic_path,
                                                    semantic.width, semantic.height));
}
}  // namespace

RgbdFrame RgbdSequence::load(size_t i, const FrameLoadOptions& options) const
{
    if (i >= frames.size())
        throw std::out_of_range(
            fmt::format("RgbdSequence::load: frame {} of {} ({})", i, frames.size(), source));
    const FrameRecord& r = frames[i];
    RgbdFrame f;
    f.t = r.t;
    f.id = r.id;
    f.K = r.K;
    f.K_color = r.K_color;
    f.T_world_cam = r.T_world_cam;
    f.depth = readDepthImage(r.depth_path, depth_units_per_metre);
    checkSize(f.depth, r.K, r.depth_path, "depth");
    if (options.color && !r.color_path.empty())
    {
        f.color = readColorImage(r.color_path);
        checkSize(f.color, r.K_color, r.color_path, "colour");
    }
    if (options.labels)
    {
        if (!r.semantic_path.empty()) f.semantic_gt = readLabelImage(r.semantic_path);
        if (!r.instance_path.empty()) f.instance_gt = readLabelImage(r.instance_path);
        checkPair(f.semantic_gt, r.semantic_path, f.instance_gt, r.instance_path, "ground-truth");
    }
    if (options.predictions)
    {
        if (!r.pred_semantic_path.empty()) f.pred_semantic = readNpzImage(r.pred_semantic_path);
        if (!r.pred_instance_path.empty()) f.pred_instance = readNpzImage(r.pred_instance_path);
        checkPair(f.pred_semantic, r.pred_semantic_path, f.pred_instance, r.pred_instance_path, "predicted");
    }
    return f;
}

}  // namespace pndt::io
