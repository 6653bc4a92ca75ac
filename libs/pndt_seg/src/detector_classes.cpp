#include <fmt/format.h>
#include <pndt/seg/detector_geometry.h>

#include <algorithm>
#include <set>

namespace pndt::seg
{
namespace
{
/// COCO-80 → NYUv2-40 names. COCO classes with an NYUv2-40 counterpart map to it; other indoor
/// objects to the nearest NYUv2-40 class (bags, electronics, small props); outdoor ones are not
/// listed (→ otherprop).
const std::map<std::string, std::string>& cocoToNyu40()
{
    static const std::map<std::string, std::string> table = {
        {"person", "person"},          {"chair", "chair"},         {"couch", "sofa"},
        {"bed", "bed"},                {"dining table", "table"},  {"tv", "television"},
        {"toilet", "toilet"},          {"refrigerator", "refrigerator"}, {"sink", "sink"},
        {"book", "books"},             {"backpack", "bag"},        {"handbag", "bag"},
        {"suitcase", "bag"},           {"bench", "chair"},         {"potted plant", "otherprop"},
        {"laptop", "otherprop"},       {"mouse", "otherprop"},     {"keyboard", "otherprop"},
        {"cell phone", "otherprop"},   {"remote", "otherprop"},    {"microwave", "otherfurniture"},
        {"oven", "otherfurniture"},    {"toaster", "otherprop"},   {"clock", "otherprop"},
        {"vase", "otherprop"},         {"cup", "otherprop"},       {"bottle", "otherprop"},
        {"bowl", "otherprop"},         {"teddy bear", "otherprop"}, {"umbrella", "otherprop"},
        {"tie", "clothes"},
    };
    return table;
}

/// The 80 COCO detection classes (the names the reachable CenterNet detector uses): the names a
/// detector description may list without a class_map entry.
const std::set<std::string>& coco80()
{
    static const std::set<std::string> names = {
        "person", "bicycle", "car", "motorcycle", "airplane", "bus", "train", "truck", "boat", "traffic light",
        "fire hydrant", "stop sign", "parking meter", "bench", "bird", "cat", "dog", "horse", "sheep", "cow",
        "elephant", "bear", "zebra", "giraffe", "backpack", "umbrella", "handbag", "tie", "suitcase", "frisbee",
        "skis", "snowboard", "sports ball", "kite", "baseball bat", "baseball glove", "skateboard", "surfboard",
        "tennis racket", "bottle", "wine glass", "cup", "fork", "knife", "spoon", "bowl", "banana", "apple",
        "sandwich", "orange", "broccoli", "carrot", "hot dog", "pizza", "donut", "cake", "chair", "couch",
        "potted plant", "bed", "dining table", "toilet", "tv", "laptop", "mouse", "remote", "keyboard",
        "cell phone", "microwave", "oven", "toaster", "sink", "refrigerator", "book", "clock", "vase", "scissors",
        "teddy bear", "hair drier", "toothbrush"};
    return names;
}
}  // namespace

std::vector<uint16_t> mapDetectorClasses(const std::vector<std::string>& names,
                                         const std::map<std::string, std::string>& overrides,
                                         const ClassSet& classes)
{
    const int otherprop = classes.find("otherprop");
    for (const auto& [name, target] : overrides)
        if (std::find(names.begin(), names.end(), name) == names.end())
            throw InputError(fmt::format("class_map has '{}', which is not one of the detector's classes", name));
    std::vector<uint16_t> ids;
    for (const auto& name : names)
    {
        std::string target;
        bool known = true;
        if (auto o = overrides.find(name); o != overrides.end())
            target = o->second;
        else if (auto t = cocoToNyu40().find(name); t != cocoToNyu40().end())
            target = t->second;
        else if (coco80().count(name))
            known = false;  // a COCO class without an indoor counterpart: otherprop
        else
            throw InputError(fmt::format(
                "detector class '{}' is not a COCO class and has no class_map entry (a typo? give it one: "
                "\"{}\": \"<class of the map's class set>\", or \"\" to ignore it)",
                name, name));
        if (!known)
        {
            ids.push_back(otherprop > 0 ? uint16_t(otherprop) : 0);
            continue;
        }
        if (target.empty() || target == "void")
        {
            ids.push_back(0);
            continue;
        }
        const int id = classes.find(target);
        if (id < 0)
            throw InputError(fmt::format("detector class '{}' maps to '{}', which is not in the class set", name, target));
        if (!classes.isThing(uint32_t(id)))
            throw InputError(fmt::format("detector class '{}' maps to '{}', a stuff class: detections are things", name,
                                         target));
        ids.push_back(uint16_t(id));
    }
    return ids;
}

}  // namespace pndt::seg
