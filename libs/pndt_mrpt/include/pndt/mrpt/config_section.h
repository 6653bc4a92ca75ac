// Strict reading of one .ini section: every value must parse completely, and
// keys nobody asked for are errors naming the section and the key.
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <set>
#include <string>

namespace pndt
{
class ConfigSection
{
   public:
    ConfigSection(const mrpt::config::CConfigFileBase& cfg, std::string section);

    bool exists() const;
    bool has(const std::string& key) const;
    void read(const std::string& key, double& v);
    void read(const std::string& key, float& v);
    void read(const std::string& key, bool& v);
    void read(const std::string& key, uint32_t& v);
    void read(const std::string& key, uint64_t& v);
    void read(const std::string& key, std::string& v);
    /// Marks keys as known without reading them (read by someone else).
    void allow(const std::string& key) { known_.insert(key); }
    /// Throws std::invalid_argument for the first key present but not known.
    void rejectUnknownKeys() const;
    const std::string& name() const { return section_; }

   private:
    std::string raw(const std::string& key);
    [[noreturn]] void fail(const std::string& key, const std::string& value, const char* expected) const;
    void rejectEmpty(const std::string& key, const std::string& value, const char* expected) const;

    const mrpt::config::CConfigFileBase& cfg_;
    std::string section_;
    std::set<std::string> known_;
};

}  // namespace pndt
