// Small helpers of the pndt_seg tests: temporary folders and description files.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace pndt::seg::test
{
/// A fresh folder of this process (two test runs at once, or ctest -j, must not share one:
/// without the pid one run removed the other's model files mid-test).
inline std::filesystem::path tempDir(const std::string& name)
{
    auto d = std::filesystem::temp_directory_path() / ("pndt_seg_test_" + std::to_string(::getpid()) + "_" + name);
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

inline std::string writeText(const std::filesystem::path& path, const std::string& text)
{
    std::ofstream(path) << text;
    return path.string();
}

}  // namespace pndt::seg::test
