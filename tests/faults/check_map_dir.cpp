// Checks an output folder of pndt-map after a fault: index.json (if present) is valid
// JSON listing only maps that exist and load, every map_*.pndt.gz present loads, and
// no temporary file is left behind (when --no-tmp is given). Exit 0 = all good,
// 1 = a problem (printed). Usage: check_map_dir DIR [--no-tmp] [--min-maps N]
#include <nlohmann/json.hpp>
#include <pndt/mrpt/map_files.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <string>

namespace fs = std::filesystem;

int main(int argc, char** argv)
{
    if (argc < 2)
    {
        std::cerr << "usage: check_map_dir DIR [--no-tmp] [--min-maps N]\n";
        return 2;
    }
    const fs::path dir = argv[1];
    bool no_tmp = false;
    size_t min_maps = 0;
    for (int i = 2; i < argc; ++i)
    {
        const std::string a = argv[i];
        if (a == "--no-tmp") no_tmp = true;
        else if (a == "--min-maps" && i + 1 < argc) min_maps = std::stoul(argv[++i]);
    }
    if (!fs::exists(dir))  // killed before it made the folder: nothing to check
    {
        std::cout << "check_map_dir: no output folder yet\n";
        return min_maps == 0 ? 0 : 1;
    }
    int problems = 0;
    const auto bad = [&](const std::string& what) {
        std::cerr << "check_map_dir: " << dir.string() << ": " << what << "\n";
        ++problems;
    };
    std::set<std::string> loaded;
    size_t maps = 0;
    for (const auto& e : fs::directory_iterator(dir))
    {
        const std::string name = e.path().filename().string();
        if (no_tmp && name.find(".tmp") != std::string::npos) bad("temporary file left behind: " + name);
        if (name.rfind("map_", 0) == 0 && name.size() > 8 && name.substr(name.size() - 8) == ".pndt.gz")
        {
            ++maps;
            try
            {
                (void)pndt::loadMapArchive(e.path().string());
                loaded.insert(name);
            }
            catch (const std::exception& ex)
            {
                bad(std::string("map does not load: ") + ex.what());
            }
        }
    }
    const fs::path index = dir / "index.json";
    size_t listed = 0;
    if (fs::exists(index))
    {
        try
        {
            std::ifstream f(index);
            const auto j = nlohmann::json::parse(f);
            if (!j.is_array()) bad("index.json is not an array");
            for (const auto& x : j)
            {
                const std::string file = x.at("file").get<std::string>();
                ++listed;
                if (!loaded.count(file)) bad("index.json lists " + file + ", which is missing or does not load");
            }
        }
        catch (const std::exception& ex)
        {
            bad(std::string("index.json is not valid: ") + ex.what());
        }
    }
    if (maps < min_maps) bad("only " + std::to_string(maps) + " maps, expected at least " + std::to_string(min_maps));
    std::cout << "check_map_dir: " << maps << " maps load, index.json lists " << listed << ", " << problems
              << " problems\n";
    return problems ? 1 : 0;
}
