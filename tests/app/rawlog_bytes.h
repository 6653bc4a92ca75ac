// Rawlog bytes for the tests that damage rawlogs: the decompressed bytes of a file, a gzip
// rawlog written from such bytes, a little-endian u32 patched in place.
#pragma once

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>

inline std::string readDecompressed(const std::filesystem::path& path)
{
    mrpt::io::CFileGZInputStream in(path.string());
    std::string out;
    char buf[4096];
    for (size_t got; (got = in.Read(buf, sizeof(buf))) > 0 && got <= sizeof(buf);) out.append(buf, got);
    return out;
}
inline void writeCompressed(const std::filesystem::path& path, const std::string& bytes)
{
    mrpt::io::CFileGZOutputStream out(path.string());
    out.Write(bytes.data(), bytes.size());
}
inline void putU32(std::string& bytes, size_t at, uint32_t v) { std::memcpy(&bytes[at], &v, sizeof(v)); }
