#include <fmt/format.h>
#include <pndt/mrpt/config_section.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace pndt
{
namespace
{
std::string trim(std::string s)
{
    const auto notspace = [](unsigned char c) { return !std::isspace(c); };
    s.erase(s.begin(), std::find_if(s.begin(), s.end(), notspace));
    s.erase(std::find_if(s.rbegin(), s.rend(), notspace).base(), s.end());
    return s;
}
}  // namespace

ConfigSection::ConfigSection(const mrpt::config::CConfigFileBase& cfg, std::string section)
    : cfg_(cfg), section_(std::move(section))
{
}

bool ConfigSection::exists() const { return cfg_.sectionExists(section_); }

bool ConfigSection::has(const std::string& key) const { return exists() && cfg_.keyExists(section_, key); }

std::string ConfigSection::raw(const std::string& key)
{
    known_.insert(key);
    return trim(cfg_.read_string(section_, key, ""));
}

void ConfigSection::fail(const std::string& key, const std::string& value, const char* expected) const
{
    throw std::invalid_argument(
        fmt::format("config section '{}', key '{}': value '{}' is not {}", section_, key, value, expected));
}

/// "key =" with nothing after it: a value lost in editing, not a request for the default.
void ConfigSection::rejectEmpty(const std::string& key, const std::string& value, const char* expected) const
{
    if (value.empty() && has(key)) fail(key, value, expected);
}

void ConfigSection::read(const std::string& key, double& v)
{
    const std::string s = raw(key);
    rejectEmpty(key, s, "a number (to keep the default, remove the key)");
    if (s.empty()) return;
    size_t used = 0;
    double x = 0;
    try
    {
        x = std::stod(s, &used);
    }
    catch (const std::exception&)
    {
        fail(key, s, "a number");
    }
    if (used != s.size() || !std::isfinite(x)) fail(key, s, "a finite number");
    v = x;
}

void ConfigSection::read(const std::string& key, float& v)
{
    double d = v;
    read(key, d);
    v = float(d);
}

void ConfigSection::read(const std::string& key, bool& v)
{
    std::string s = raw(key);
    rejectEmpty(key, s, "a boolean (to keep the default, remove the key)");
    if (s.empty()) return;
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (s == "1" || s == "true" || s == "yes" || s == "on")
        v = true;
    else if (s == "0" || s == "false" || s == "no" || s == "off")
        v = false;
    else
        fail(key, s, "a boolean (true/false)");
}

void ConfigSection::read(const std::string& key, uint64_t& v)
{
    const std::string s = raw(key);
    rejectEmpty(key, s, "a non-negative integer (to keep the default, remove the key)");
    if (s.empty()) return;
    size_t used = 0;
    unsigned long long x = 0;
    try
    {
        if (s[0] == '-') throw std::invalid_argument("negative");
        x = std::stoull(s, &used);
    }
    catch (const std::exception&)
    {
        fail(key, s, "a non-negative integer");
    }
    if (used != s.size()) fail(key, s, "a non-negative integer");
    v = x;
}

void ConfigSection::read(const std::string& key, uint32_t& v)
{
    uint64_t x = v;
    read(key, x);
    if (x > 0xFFFFFFFFull) fail(key, std::to_string(x), "a 32-bit integer");
    v = uint32_t(x);
}

void ConfigSection::read(const std::string& key, std::string& v)
{
    const std::string s = raw(key);
    if (!s.empty()) v = s;
}

void ConfigSection::rejectUnknownKeys() const
{
    if (!exists()) return;
    std::vector<std::string> keys;
    cfg_.getAllKeys(section_, keys);
    for (const std::string& k : keys)
        if (!known_.count(k))
        {
            std::string list;
            for (const auto& kk : known_) list += (list.empty() ? "" : ", ") + kk;
            throw std::invalid_argument(
                fmt::format("config section '{}': unknown key '{}' (known keys: {})", section_, k, list));
        }
}

}  // namespace pndt
