#include <fmt/format.h>
#include <pndt/seg/detector_geometry.h>

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
}  // namespace

std::vector<uint16_t> mapDetectorClasses(const std::vector<std::string>& names,
                                         const std::map<std::string, std::string>& overrides,
                                         const ClassSet& classes)
{
    const int otherprop = classes.find("otherprop");
    std::vector<uint16_t> ids;
    for (const auto& name : names)
    {
        std::string target;
        bool known = true;
        if (auto o = overrides.find(name); o != overrides.end())
            target = o->second;
        else if (auto t = cocoToNyu40().find(name); t != cocoToNyu40().end())
            target = t->second;
        else
            known = false;
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
