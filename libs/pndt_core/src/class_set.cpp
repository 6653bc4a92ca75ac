#include <pndt/class_set.h>

#include <cmath>
#include <stdexcept>

namespace pndt
{
ClassSet::ClassSet(std::vector<Class> classes) : classes_(std::move(classes))
{
    if (classes_.empty() || classes_.size() > 255)
        throw std::invalid_argument("a class set holds 1 to 255 classes (class 0 = void), not " +
                                    std::to_string(classes_.size()));
    // Class 0 is read as "no prediction" wherever labels are: a set whose class 0 is a real
    // class ("road") lost it without a word.
    if (classes_[0].name != "void" || classes_[0].is_thing)
        throw std::invalid_argument("class 0 must be 'void' (no prediction, stuff), not '" + classes_[0].name + "'" +
                                    (classes_[0].is_thing ? " (a thing)" : ""));
    // Names are how configs, queries and reports find a class: two of one name made one
    // "class" of two ids (instances.json listed both under it, a query counted one).
    for (size_t i = 0; i < classes_.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (classes_[i].name == classes_[j].name)
                throw std::invalid_argument("class name '" + classes_[i].name + "' is given twice (classes " +
                                            std::to_string(j) + " and " + std::to_string(i) + ")");
}

ClassSet ClassSet::nyuv2_40()
{
    static const char* names[] = {"void",       "wall",        "floor",          "cabinet",      "bed",
                                  "chair",      "sofa",        "table",          "door",         "window",
                                  "bookshelf",  "picture",     "counter",        "blinds",       "desk",
                                  "shelves",    "curtain",     "dresser",        "pillow",       "mirror",
                                  "floor mat",  "clothes",     "ceiling",        "books",        "refrigerator",
                                  "television", "paper",       "towel",          "shower curtain", "box",
                                  "whiteboard", "person",      "night stand",    "toilet",       "sink",
                                  "lamp",       "bathtub",     "bag",            "otherstructure", "otherfurniture",
                                  "otherprop"};
    std::vector<Class> c;
    for (int i = 0; i < 41; ++i)
    {
        const bool stuff = i == 0 || i == 1 || i == 2 || i == 22;
        c.push_back({names[i], !stuff});
    }
    return ClassSet(std::move(c));
}

int ClassSet::find(const std::string& name) const
{
    for (size_t i = 0; i < classes_.size(); ++i)
        if (classes_[i].name == name) return int(i);
    return -1;
}

bool ClassSet::operator==(const ClassSet& o) const
{
    if (classes_.size() != o.classes_.size()) return false;
    for (size_t i = 0; i < classes_.size(); ++i)
        if (classes_[i].name != o.classes_[i].name || classes_[i].is_thing != o.classes_[i].is_thing) return false;
    return true;
}

Rgb classColor(uint32_t id)
{
    // PASCAL-VOC bit-interleaved colormap.
    Rgb c;
    uint32_t v = id;
    for (int shift = 7; shift >= 0 && v; --shift, v >>= 3)
    {
        c.r |= uint8_t(((v >> 0) & 1) << shift);
        c.g |= uint8_t(((v >> 1) & 1) << shift);
        c.b |= uint8_t(((v >> 2) & 1) << shift);
    }
    return c;
}

Rgb instanceColor(uint32_t id)
{
    if (id == 0) return {128, 128, 128};
    // Golden-ratio hue walk: neighbouring ids get far-apart hues.
    const double h = std::fmod(id * 0.618033988749895, 1.0) * 6.0;
    const double s = 0.75, v = 0.95;
    const int i = int(h);
    const double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    double r, g, b;
    switch (i)
    {
        case 0: r = v, g = t, b = p; break;
        case 1: r = q, g = v, b = p; break;
        case 2: r = p, g = v, b = t; break;
        case 3: r = p, g = q, b = v; break;
        case 4: r = t, g = p, b = v; break;
        default: r = v, g = p, b = q; break;
    }
    return {uint8_t(r * 255), uint8_t(g * 255), uint8_t(b * 255)};
}

}  // namespace pndt
