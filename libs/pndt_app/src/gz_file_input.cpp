#include "gz_file_input.h"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <climits>
#include <filesystem>
#include <stdexcept>

namespace pndt::app
{
namespace
{
gzFile handle(void* p) { return static_cast<gzFile>(p); }
}  // namespace

GzFileInput::GzFileInput(const std::string& path) : path_(path)
{
    std::error_code ec;
    file_size_ = std::filesystem::file_size(path, ec);
    if (ec) throw std::runtime_error(fmt::format("{}: cannot open ({})", path, ec.message()));
    gz_ = gzopen(path.c_str(), "rb");
    if (!gz_) throw std::runtime_error(fmt::format("{}: cannot open", path));
    gzbuffer(handle(gz_), 1 << 15);  // small: compressedPosition() runs ahead by up to twice this
}

GzFileInput::~GzFileInput()
{
    if (gz_) gzclose(handle(gz_));
}

size_t GzFileInput::Read(void* buffer, size_t count)
{
    size_t total = 0;
    auto* out = static_cast<char*>(buffer);
    while (total < count)
    {
        // gzread takes an unsigned int: large images are read in pieces.
        const unsigned chunk = unsigned(std::min<size_t>(count - total, size_t(INT_MAX)));
        const int got = gzread(handle(gz_), out + total, chunk);
        if (got < 0)
        {
            int code = 0;
            const char* message = gzerror(handle(gz_), &code);
            throw std::runtime_error(fmt::format("the compressed data ends early or is corrupt ({})", message));
        }
        total += size_t(got);
        position_ += uint64_t(got);
        if (unsigned(got) < chunk)
        {
            // The end of the file: zlib says Z_BUF_ERROR when it came inside the gzip stream
            // (a file cut in its last bytes, the CRC trailer, would otherwise read as complete).
            int code = 0;
            const char* message = gzerror(handle(gz_), &code);
            if (code == Z_BUF_ERROR)
                throw std::runtime_error(fmt::format("the compressed data ends early ({})", message));
            break;
        }
    }
    return total;
}

size_t GzFileInput::Write(const void*, size_t) { throw std::logic_error(path_ + ": read-only"); }

uint64_t GzFileInput::Seek(int64_t, CStream::TSeekOrigin) { throw std::logic_error(path_ + ": cannot seek"); }

uint64_t GzFileInput::compressedPosition() const
{
    const z_off_t at = gzoffset(handle(gz_));
    return at < 0 ? 0 : std::min<uint64_t>(uint64_t(at), file_size_);
}
}  // namespace pndt::app
