// The ini layering: the input is split at the first NUL byte into a base file and
// an override file; the rest after a second NUL, line by line, is "section.key=value"
// command-line overrides.
#include <pndt/app/layered_config.h>

#include "fuzz_util.h"

#include <exception>
#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string all(reinterpret_cast<const char*>(data), size);
    const size_t a = all.find('\0');
    const std::string base = all.substr(0, a);
    std::string layer, rest;
    if (a != std::string::npos)
    {
        const size_t b = all.find('\0', a + 1);
        layer = all.substr(a + 1, b == std::string::npos ? std::string::npos : b - a - 1);
        if (b != std::string::npos) rest = all.substr(b + 1);
    }
    const std::string p1 = pndt_fuzz::writeInput(reinterpret_cast<const uint8_t*>(base.data()), base.size(), "-a.ini");
    const std::string p2 = pndt_fuzz::writeInput(reinterpret_cast<const uint8_t*>(layer.data()), layer.size(), "-b.ini");
    std::vector<std::string> overrides;
    std::istringstream lines(rest);
    for (std::string line; std::getline(lines, line);) overrides.push_back(line);
    try
    {
        const auto cfg = pndt::app::loadLayeredConfig({p1, p2}, overrides);
        pndt::app::rejectUnknownSections(cfg, {"PanopticNDTMap", "mapping"}, {"map_"});
    }
    catch (const std::exception&)
    {
    }
    return 0;
}
