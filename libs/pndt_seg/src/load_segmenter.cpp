#include <pndt/seg/segmenter.h>

#include "segmenters.h"

namespace pndt::seg
{
std::unique_ptr<Segmenter> loadSegmenter(const std::string& description_path, const ClassSet& classes,
                                         const SegmenterOptions& options)
{
    ModelDescription d = loadModelDescription(description_path);
    if (d.kind == "detector") return std::make_unique<DetectorSegmenter>(std::move(d), classes, options);
    return std::make_unique<NetworkSegmenter>(std::move(d), classes);
}

}  // namespace pndt::seg
