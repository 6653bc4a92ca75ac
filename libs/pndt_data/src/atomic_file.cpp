#include "pndt/data/atomic_file.h"

#include <pndt/io/atomic_file.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace pndt::data
{
void writeFileAtomic(const std::string& path, const std::function<void(std::ostream&)>& fill)
{
    const fs::path p(path);
    if (p.has_parent_path())
    {
        try
        {
            io::ensureDirectory(p.parent_path().string());
        }
        catch (const io::WriteError& e)
        {
            throw std::runtime_error(path + ": " + e.what());
        }
    }
    // pndt::io does the temporary, fsync and rename; this adds folders and streams.
    io::writeFileAtomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw std::runtime_error(path + ": cannot open " + tmp + " for writing: " + std::strerror(errno));
        fill(out);
        io::closeWrittenStream(out, path);  // a WriteError is a std::runtime_error
    });
}

void writeFileAtomic(const std::string& path, const std::string& bytes)
{
    writeFileAtomic(path, [&](std::ostream& o) { o.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}

}  // namespace pndt::data
