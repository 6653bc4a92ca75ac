// Loading the map to navigate in (map_source.h).
#include <fmt/format.h>
#include <pndt/mrpt/map_files.h>
#include <pndt/nav/map_source.h>

namespace fs = std::filesystem;

namespace pndt::nav
{
namespace
{
bool isMapFile(const fs::path& p)
{
    const std::string n = p.filename().string();
    return n.size() > 8 && n.compare(n.size() - 8, 8, ".pndt.gz") == 0;
}
}  // namespace

fs::path newestMapFile(const fs::path& dir)
{
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw InputError(fmt::format("{}: not a folder", dir.string()));
    fs::path best;
    fs::file_time_type best_t{};
    for (const auto& e : fs::directory_iterator(dir))
    {
        if (!e.is_regular_file() || !isMapFile(e.path())) continue;
        const auto t = e.last_write_time();
        if (best.empty() || t > best_t || (t == best_t && e.path().filename() > best.filename()))
        {
            best = e.path();
            best_t = t;
        }
    }
    if (best.empty()) throw InputError(fmt::format("{}: no *.pndt.gz map in this folder", dir.string()));
    return best;
}

LoadedMap loadNavigationMap(const fs::path& path)
{
    LoadedMap m;
    m.file = fs::is_directory(path) ? newestMapFile(path) : path;
    if (!fs::exists(m.file)) throw InputError(fmt::format("{}: no such file", m.file.string()));
    m.stamp = fs::last_write_time(m.file);
    try
    {
        m.map = loadMapArchive(m.file.string());
    }
    catch (const std::exception& e)
    {
        throw InputError(e.what());
    }
    return m;
}

bool reloadIfNewer(const fs::path& source, LoadedMap& current)
{
    if (!fs::is_directory(source)) return false;
    const fs::path newest = newestMapFile(source);
    const auto t = fs::last_write_time(newest);
    if (newest == current.file && t == current.stamp) return false;
    if (t < current.stamp) return false;
    current = loadNavigationMap(newest);
    return true;
}

}  // namespace pndt::nav
