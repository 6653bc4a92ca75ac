#include <pndt/seg/model_description.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>

namespace pndt::seg
{
namespace
{
using nlohmann::json;
namespace fs = std::filesystem;

struct Reader
{
    std::string file;

    [[noreturn]] void fail(const std::string& what) const { throw InputError(fmt::format("{}: {}", file, what)); }

    void onlyKeys(const json& j, const std::string& where, std::initializer_list<const char*> keys) const
    {
        if (!j.is_object()) fail(fmt::format("'{}' must be a JSON object", where));
        const std::set<std::string> allowed(keys.begin(), keys.end());
        for (const auto& [k, v] : j.items())
            if (!allowed.count(k))
            {
                std::string list;
                for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
                fail(fmt::format("unknown key '{}' in {} (allowed: {})", k, where, list));
            }
    }
    template <typename T>
    T get(const json& j, const std::string& key, const std::string& where) const
    {
        if (!j.contains(key)) fail(fmt::format("missing key '{}' in {}", key, where));
        try
        {
            return j.at(key).get<T>();
        }
        catch (const json::exception&)
        {
            fail(fmt::format("key '{}' in {} has the wrong type ({})", key, where, j.at(key).dump()));
        }
    }
    template <typename T>
    void optional(const json& j, const std::string& key, const std::string& where, T& value) const
    {
        if (j.contains(key)) value = get<T>(j, key, where);
    }
    std::string oneOf(const json& j, const std::string& key, const std::string& where,
                      std::initializer_list<const char*> allowed, const std::string& fallback) const
    {
        const std::string v = j.contains(key) ? get<std::string>(j, key, where) : fallback;
        for (const char* a : allowed)
            if (v == a) return v;
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : " | ") + std::string(a);
        fail(fmt::format("'{}' in {} must be {} (got '{}')", key, where, list, v));
    }
};

void readPostprocess(const Reader& r, const json& j, PostprocessOptions& o)
{
    const std::string w = "\"postprocess\"";
    r.onlyKeys(j, w, {"center_threshold", "nms_kernel", "top_k", "center_activation", "semantic_activation",
                      "offset_order", "offset_scale"});
    r.optional(j, "center_threshold", w, o.center_threshold);
    r.optional(j, "nms_kernel", w, o.nms_kernel);
    r.optional(j, "top_k", w, o.top_k);
    r.optional(j, "offset_scale", w, o.offset_scale);
    o.center_is_logit = r.oneOf(j, "center_activation", w, {"none", "sigmoid"}, "none") == "sigmoid";
    o.semantic_is_logit = r.oneOf(j, "semantic_activation", w, {"softmax", "none"}, "softmax") == "softmax";
    o.offset_yx = r.oneOf(j, "offset_order", w, {"yx", "xy"}, "yx") == "yx";
    if (o.nms_kernel < 1 || o.nms_kernel % 2 == 0) r.fail(fmt::format("nms_kernel must be odd (got {})", o.nms_kernel));
    if (o.top_k < 1) r.fail("top_k must be >= 1");
}

void readDetector(const Reader& r, const json& j, CenterNetDecodeOptions& o)
{
    const std::string w = "\"detector\"";
    r.onlyKeys(j, w, {"score_threshold", "top_k", "stride", "box_scale"});
    r.optional(j, "score_threshold", w, o.score_threshold);
    r.optional(j, "top_k", w, o.top_k);
    r.optional(j, "stride", w, o.stride);
    r.optional(j, "box_scale", w, o.box_scale);
    if (o.stride < 1 || o.top_k < 1 || !(o.box_scale > 0)) r.fail("detector: stride, top_k and box_scale must be > 0");
}

void readGeometry(const Reader& r, const json& j, GeometryLabelOptions& o)
{
    const std::string w = "\"geometry\"";
    r.onlyKeys(j, w, {"plane_sample_step", "plane_inlier_distance", "horizontal_tolerance_deg",
                      "vertical_tolerance_deg", "min_plane_share", "max_planes", "min_wall_extent",
                      "ransac_iterations", "seed", "segment_depth_step", "segment_footprints", "min_mask_share"});
    r.optional(j, "plane_sample_step", w, o.plane_sample_step);
    r.optional(j, "plane_inlier_distance", w, o.plane_inlier_distance);
    r.optional(j, "horizontal_tolerance_deg", w, o.horizontal_tolerance_deg);
    r.optional(j, "vertical_tolerance_deg", w, o.vertical_tolerance_deg);
    r.optional(j, "min_plane_share", w, o.min_plane_share);
    r.optional(j, "max_planes", w, o.max_planes);
    r.optional(j, "min_wall_extent", w, o.min_wall_extent);
    r.optional(j, "ransac_iterations", w, o.ransac_iterations);
    r.optional(j, "seed", w, o.seed);
    r.optional(j, "segment_depth_step", w, o.segment_depth_step);
    r.optional(j, "segment_footprints", w, o.segment_footprints);
    r.optional(j, "min_mask_share", w, o.min_mask_share);
}

InputSpec readInput(const Reader& r, const json& j, size_t index)
{
    const std::string w = fmt::format("inputs[{}]", index);
    r.onlyKeys(j, w, {"name", "kind", "scale", "mean", "std"});
    InputSpec s;
    s.name = r.get<std::string>(j, "name", w);
    s.kind = r.oneOf(j, "kind", w, {"rgb", "bgr", "depth"}, "rgb");
    r.optional(j, "scale", w, s.scale);
    r.optional(j, "mean", w, s.mean);
    r.optional(j, "std", w, s.std);
    const size_t ch = size_t(s.channels());
    for (auto* v : {&s.mean, &s.std})
    {
        if (v->size() == 1) v->resize(ch, v->front());
        if (v->size() != ch) r.fail(fmt::format("{}: mean and std need 1 or {} entries", w, ch));
    }
    for (float sd : s.std)
        if (!(sd > 0)) r.fail(fmt::format("{}: std entries must be > 0", w));
    return s;
}
}  // namespace

std::vector<std::string> ModelDescription::outputNames() const
{
    if (kind == "detector") return {heatmap_output, box_size_output};
    if (kind == "semantic") return {semantic_output};
    return {semantic_output, center_output, offset_output};
}

ModelDescription loadModelDescription(const std::string& path)
{
    const Reader r{path};
    std::ifstream f(path);
    if (!f) r.fail("cannot open the model description file");
    json j;
    try
    {
        j = json::parse(f);
    }
    catch (const json::parse_error& e)
    {
        r.fail(fmt::format("not valid JSON ({})", e.what()));
    }
    const std::string top = "the description";
    r.onlyKeys(j, top, {"format", "name", "onnx", "kind", "input_size", "inputs", "outputs", "classes", "class_map",
                        "postprocess", "detector", "geometry"});
    ModelDescription d;
    d.path = path;
    const auto format = r.get<std::string>(j, "format", top);
    if (format != "pndt-segmentation-model/1")
        r.fail(fmt::format("format '{}' is not 'pndt-segmentation-model/1'", format));
    r.optional(j, "name", top, d.name);
    const fs::path onnx = r.get<std::string>(j, "onnx", top);
    d.onnx_path = (onnx.is_absolute() ? onnx : fs::path(path).parent_path() / onnx).string();
    d.kind = r.oneOf(j, "kind", top, {"panoptic", "semantic", "detector"}, "");

    const auto size = r.get<std::vector<int>>(j, "input_size", top);
    if (size.size() != 2 || size[0] < 1 || size[1] < 1 || size[0] > 8192 || size[1] > 8192)
        r.fail("input_size must be [width, height] with 1..8192 pixels each");
    d.input_width = size[0];
    d.input_height = size[1];

    const json& inputs = j.contains("inputs") ? j.at("inputs") : json();
    if (!inputs.is_array() || inputs.empty()) r.fail("'inputs' must be a non-empty array");
    for (size_t i = 0; i < inputs.size(); ++i) d.inputs.push_back(readInput(r, inputs[i], i));

    const json& out = j.contains("outputs") ? j.at("outputs") : json();
    const std::string w = "\"outputs\"";
    if (d.kind == "detector")
    {
        r.onlyKeys(out, w, {"heatmap", "box_size"});
        d.heatmap_output = r.get<std::string>(out, "heatmap", w);
        d.box_size_output = r.get<std::string>(out, "box_size", w);
    }
    else if (d.kind == "semantic")
    {
        r.onlyKeys(out, w, {"semantic"});
        d.semantic_output = r.get<std::string>(out, "semantic", w);
    }
    else
    {
        r.onlyKeys(out, w, {"semantic", "center", "offset"});
        d.semantic_output = r.get<std::string>(out, "semantic", w);
        d.center_output = r.get<std::string>(out, "center", w);
        d.offset_output = r.get<std::string>(out, "offset", w);
    }
    d.classes = r.get<std::vector<std::string>>(j, "classes", top);
    if (d.classes.empty() || d.classes.size() > 256) r.fail("'classes' must list 1..256 names");
    if (j.contains("class_map"))
    {
        if (d.kind != "detector") r.fail("'class_map' is for detector models only");
        d.class_map = r.get<std::map<std::string, std::string>>(j, "class_map", top);
    }
    if (j.contains("postprocess")) readPostprocess(r, j.at("postprocess"), d.postprocess);
    if (j.contains("detector")) readDetector(r, j.at("detector"), d.detector);
    if (j.contains("geometry")) readGeometry(r, j.at("geometry"), d.geometry);
    return d;
}

std::vector<uint16_t> mapModelClasses(const ModelDescription& d, const ClassSet& classes)
{
    std::vector<uint16_t> ids;
    for (const auto& name : d.classes)
    {
        const int id = classes.find(name);
        if (id < 0)
            throw InputError(fmt::format("{}: class '{}' is not in the map's class set ({} classes, e.g. '{}')",
                                         d.path, name, classes.size(), classes.size() > 1 ? classes.name(1) : ""));
        ids.push_back(uint16_t(id));
    }
    return ids;
}

}  // namespace pndt::seg
