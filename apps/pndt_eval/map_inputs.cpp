#include "map_inputs.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <pndt/types.h>

#include <filesystem>
#include <fstream>

namespace pndt::evalapp
{
namespace fs = std::filesystem;

std::vector<std::string> mapFiles(const std::string& map_or_folder)
{
    if (!fs::exists(map_or_folder)) throw InputError(fmt::format("{}: no such file or folder", map_or_folder));
    if (!fs::is_directory(map_or_folder)) return {map_or_folder};
    const fs::path index = fs::path(map_or_folder) / "index.json";
    std::ifstream f(index);
    if (!f) throw InputError(fmt::format("{}: no index.json (not a pndt-map output folder)", map_or_folder));
    nlohmann::json j;
    try
    {
        f >> j;
    }
    catch (const std::exception& e)
    {
        throw InputError(fmt::format("{}: not valid JSON: {}", index.string(), e.what()));
    }
    if (!j.is_array()) throw InputError(fmt::format("{}: expected a JSON array of maps", index.string()));
    std::vector<std::string> out;
    for (const auto& e : j)
    {
        if (!e.is_object() || !e.contains("file") || !e["file"].is_string())
            throw InputError(fmt::format("{}: an entry without a \"file\" name", index.string()));
        const fs::path p = fs::path(map_or_folder) / e["file"].get<std::string>();
        if (!fs::exists(p)) throw InputError(fmt::format("{}: lists {}, which does not exist", index.string(), p.string()));
        out.push_back(p.string());
    }
    if (out.empty()) throw InputError(fmt::format("{}: lists no maps", index.string()));
    return out;
}
}  // namespace pndt::evalapp
