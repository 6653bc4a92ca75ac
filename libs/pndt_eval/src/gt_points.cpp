#include <fmt/format.h>
#include <pndt/eval/gt_points.h>
#include <pndt/types.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace pndt::eval
{
namespace
{
struct Property
{
    std::string name;
    int bytes = 0;  // binary size
    char kind = 'f';  // 'f' float, 'i' signed, 'u' unsigned
};

Property propertyOf(const std::string& type, const std::string& name, const std::string& path)
{
    if (type == "float" || type == "float32") return {name, 4, 'f'};
    if (type == "double" || type == "float64") return {name, 8, 'f'};
    if (type == "char" || type == "int8") return {name, 1, 'i'};
    if (type == "uchar" || type == "uint8") return {name, 1, 'u'};
    if (type == "short" || type == "int16") return {name, 2, 'i'};
    if (type == "ushort" || type == "uint16") return {name, 2, 'u'};
    if (type == "int" || type == "int32") return {name, 4, 'i'};
    if (type == "uint" || type == "uint32") return {name, 4, 'u'};
    throw InputError(fmt::format("{}: PLY property '{}' has the unknown type '{}'", path, name, type));
}

double decode(const Property& p, const char* b)
{
    switch (p.bytes * 4 + (p.kind == 'f' ? 0 : p.kind == 'i' ? 1 : 2))
    {
        case 16: { float v; std::memcpy(&v, b, 4); return v; }
        case 32: { double v; std::memcpy(&v, b, 8); return v; }
        case 5: { int8_t v; std::memcpy(&v, b, 1); return v; }
        case 6: { uint8_t v; std::memcpy(&v, b, 1); return v; }
        case 9: { int16_t v; std::memcpy(&v, b, 2); return v; }
        case 10: { uint16_t v; std::memcpy(&v, b, 2); return v; }
        case 17: { int32_t v; std::memcpy(&v, b, 4); return v; }
        case 18: { uint32_t v; std::memcpy(&v, b, 4); return v; }
    }
    return 0;
}
}  // namespace

GtPoints readPlyPoints(const std::string& path, bool with_labels)
{
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(fmt::format("{}: cannot open", path));
    std::string line;
    if (!std::getline(f, line) || line.rfind("ply", 0) != 0) throw InputError(fmt::format("{}: not a PLY file", path));
    bool binary = false, in_vertex = false, seen_element = false;
    uint64_t count = 0;
    std::vector<Property> props;
    for (;;)
    {
        if (!std::getline(f, line)) throw InputError(fmt::format("{}: PLY header ends before end_header", path));
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream in(line);
        std::string word;
        in >> word;
        if (word == "end_header") break;
        if (word == "format")
        {
            std::string fmt_name;
            in >> fmt_name;
            if (fmt_name == "binary_little_endian")
                binary = true;
            else if (fmt_name != "ascii")
                throw InputError(fmt::format("{}: PLY format '{}' is not supported (ascii, binary_little_endian)", path,
                                             fmt_name));
        }
        else if (word == "element")
        {
            std::string name;
            uint64_t n = 0;
            in >> name >> n;
            if (!in) throw InputError(fmt::format("{}: bad PLY element line '{}'", path, line));
            if (!seen_element) count = n;
            if (!seen_element && name != "vertex")
                throw InputError(fmt::format("{}: the PLY's first element is '{}', not 'vertex'", path, name));
            in_vertex = !seen_element;
            seen_element = true;
            if (!in_vertex) continue;
        }
        else if (word == "property" && in_vertex)
        {
            std::string type, name;
            in >> type >> name;
            if (type == "list") throw InputError(fmt::format("{}: list property in the vertex element", path));
            props.push_back(propertyOf(type, name, path));
        }
    }
    if (!seen_element) throw InputError(fmt::format("{}: PLY has no vertex element", path));
    int ix = -1, iy = -1, iz = -1, il = -1;
    size_t stride = 0;
    for (size_t i = 0; i < props.size(); ++i)
    {
        const std::string& n = props[i].name;
        ix = n == "x" ? int(i) : ix;
        iy = n == "y" ? int(i) : iy;
        iz = n == "z" ? int(i) : iz;
        il = n == "label" ? int(i) : il;
        stride += size_t(props[i].bytes);
    }
    if (ix < 0 || iy < 0 || iz < 0) throw InputError(fmt::format("{}: PLY vertices have no x, y and z", path));
    if (with_labels && il < 0)
        throw InputError(fmt::format("{}: PLY vertices have no 'label' property (sem << 16 | ins)", path));
    // The body must hold the vertices before anything is allocated for them.
    const auto body = uint64_t(std::filesystem::file_size(path)) - uint64_t(f.tellg());
    const uint64_t need = binary ? count * stride : count * 2 * props.size();  // ascii: >= 2 bytes a value
    if (need > body)
        throw InputError(fmt::format("{}: truncated: {} vertices need {} bytes, the file has {} after the header", path,
                                     count, need, body));
    GtPoints out;
    out.points.resize(count);
    if (with_labels) out.labels.resize(count);
    std::vector<char> rec(stride);
    std::vector<double> v(props.size());
    for (uint64_t k = 0; k < count; ++k)
    {
        if (binary)
        {
            if (!f.read(rec.data(), std::streamsize(stride)))
                throw InputError(fmt::format("{}: truncated at vertex {} of {}", path, k, count));
            size_t off = 0;
            for (size_t i = 0; i < props.size(); ++i)
            {
                v[i] = decode(props[i], rec.data() + off);
                off += size_t(props[i].bytes);
            }
        }
        else
            for (size_t i = 0; i < props.size(); ++i)
                if (!(f >> v[i])) throw InputError(fmt::format("{}: truncated or bad number at vertex {} of {}", path, k, count));
        out.points[k] = {v[size_t(ix)], v[size_t(iy)], v[size_t(iz)]};
        if (!out.points[k].allFinite()) throw InputError(fmt::format("{}: vertex {} is not finite", path, k));
        if (with_labels)
        {
            const double l = v[size_t(il)];
            if (!(l >= 0 && l <= double(UINT32_MAX) && l == std::floor(l)))
                throw InputError(fmt::format("{}: vertex {}: label {} is not a whole number in 0..{}", path, k, l, UINT32_MAX));
            out.labels[k] = uint32_t(l);
        }
    }
    return out;
}

std::vector<uint32_t> panopticFromShifted(const std::vector<uint32_t>& labels, uint32_t shift, const std::string& source)
{
    if (shift == 0 || shift > 65536)
        throw InputError(fmt::format("{}: label shift {} (instances must fit 16 bits)", source, shift));
    std::vector<uint32_t> out(labels.size());
    for (size_t i = 0; i < labels.size(); ++i)
    {
        const uint32_t sem = labels[i] / shift, ins = labels[i] % shift;
        if (sem > 0xFFFF)
            throw InputError(fmt::format("{}: line {}: label {} gives class {} (shift {})", source, i + 1, labels[i], sem,
                                         shift));
        out[i] = (sem << 16) | ins;
    }
    return out;
}

}  // namespace pndt::eval
