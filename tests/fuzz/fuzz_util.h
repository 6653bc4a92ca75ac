// Shared helpers of the libFuzzer targets: our readers take file paths, so each
// input is written to a per-process file in /dev/shm (or $TMPDIR) first.
#pragma once
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace pndt_fuzz
{
/// Writes the input to a file ending in `suffix` and returns its path (the same
/// path for every input of a process, so no file piles up).
inline std::string writeInput(const uint8_t* data, size_t size, const std::string& suffix)
{
    static const std::string dir = [] {
        const char* t = std::getenv("PNDT_FUZZ_TMP");
        return std::string(t ? t : (access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp"));
    }();
    const std::string path = dir + "/pndt-fuzz-" + std::to_string(getpid()) + suffix;
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path;
}

/// Splits off the first byte as a selector (which reader / format to exercise).
inline uint8_t takeSelector(const uint8_t*& data, size_t& size)
{
    if (size == 0) return 0;
    const uint8_t s = data[0];
    ++data;
    --size;
    return s;
}
}  // namespace pndt_fuzz
