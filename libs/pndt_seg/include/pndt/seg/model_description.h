// The model description file: a JSON file next to an .onnx network that says how to feed it and
// how to read its outputs (doc/segmentation.md has the full reference and examples).
//
// {
//   "format": "pndt-segmentation-model/1",
//   "name": "...",                       free text
//   "onnx": "model.onnx",                relative to the description file
//   "kind": "panoptic" | "semantic" | "detector",
//   "input_size": [width, height],       the frame is resized to this (and labels back)
//   "inputs": [{"name": "rgb", "kind": "rgb" | "bgr" | "depth",
//               "scale": 1.0, "mean": [..], "std": [..]}],   value = (pixel·scale − mean) / std
//                                         (depth pixels are metres; mean/std have 1 or 3 entries)
//   "outputs": {"semantic": "...", "center": "...", "offset": "..."}     panoptic
//              {"semantic": "..."}                                       semantic
//              {"heatmap": "...", "box_size": "..."}                     detector
//   "classes": ["void", "wall", ...],    output channel i → a class name of the map's class set
//                                         (detector: the detector's own names, e.g. COCO)
//   "class_map": {"couch": "sofa"},      detector only: overrides of the built-in COCO table
//   "postprocess": {...PostprocessOptions keys...},
//   "detector": {...CenterNetDecodeOptions keys...},
//   "geometry": {...GeometryLabelOptions keys...}
// }
// Unknown keys are errors (a typo must not silently fall back to a default).
#pragma once

#include <pndt/class_set.h>
#include <pndt/seg/detector_geometry.h>
#include <pndt/seg/panoptic_postprocess.h>

#include <map>
#include <string>
#include <vector>

namespace pndt::seg
{
struct InputSpec
{
    std::string name;          ///< network input name
    std::string kind = "rgb";  ///< rgb | bgr | depth
    float scale = 1.0f;
    std::vector<float> mean{0.f};
    std::vector<float> std{1.f};
    int channels() const { return kind == "depth" ? 1 : 3; }
};

struct ModelDescription
{
    std::string path;       ///< the description file
    std::string name;
    std::string onnx_path;  ///< absolute or relative to the working directory (resolved)
    std::string kind;       ///< panoptic | semantic | detector
    int input_width = 0, input_height = 0;
    std::vector<InputSpec> inputs;
    std::string semantic_output, center_output, offset_output;  ///< panoptic / semantic
    std::string heatmap_output, box_size_output;                ///< detector
    std::vector<std::string> classes;                           ///< per output channel
    std::map<std::string, std::string> class_map;               ///< detector overrides
    PostprocessOptions postprocess;
    CenterNetDecodeOptions detector;
    GeometryLabelOptions geometry;

    /// Output names the network must have, in forward() order.
    std::vector<std::string> outputNames() const;
};

/// Parses and validates a description file. Throws InputError naming the file and the key.
ModelDescription loadModelDescription(const std::string& path);

/// Output channel → class id in `classes` (panoptic / semantic models): every name must exist
/// in `classes`; throws InputError naming the description file and the unknown class.
std::vector<uint16_t> mapModelClasses(const ModelDescription& d, const ClassSet& classes);

}  // namespace pndt::seg
