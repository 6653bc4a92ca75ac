#include "zip_reader.h"

#include "text_util.h"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <limits>

namespace pndt::io::detail
{
namespace
{
constexpr uint32_t kSigLocal = 0x04034b50;
constexpr uint32_t kSigCentral = 0x02014b50;
constexpr uint32_t kSigEocd = 0x06054b50;
constexpr uint32_t kSigZip64Eocd = 0x06064b50;
constexpr uint32_t kSigZip64Locator = 0x07064b50;
constexpr uint64_t kMaxEntryBytes = uint64_t{1} << 31;  // 2 GiB: far beyond any prediction image
constexpr uint64_t kMaxDeflateRatio = 1032;  // deflate's largest expansion (258-byte matches in 2 bits)

/// Bounds-checked little-endian reader over the file bytes.
struct Reader
{
    const std::string& b;
    const std::string& path;

    [[noreturn]] void bad(const std::string& what) const
    {
        failFile(path, "malformed zip: " + what);
    }
    void need(uint64_t off, uint64_t n, const char* what) const
    {
        if (off > b.size() || n > b.size() - off)
            bad(fmt::format("truncated file ({} at offset {} needs {} bytes, file has {})", what,
                            off, n, b.size()));
    }
    uint16_t u16(uint64_t off) const
    {
        need(off, 2, "field");
        const auto* p = reinterpret_cast<const unsigned char*>(b.data() + off);
        return static_cast<uint16_t>(p[0] | (p[1] << 8));
    }
    uint32_t u32(uint64_t off) const
    {
        need(off, 4, "field");
        const auto* p = reinterpret_cast<const unsigned char*>(b.data() + off);
        return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
               (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
    }
    uint64_t u64(uint64_t off) const
    {
        return static_cast<uint64_t>(u32(off)) | (static_cast<uint64_t>(u32(off + 4)) << 32);
    }
};
}  // namespace

ZipArchive::ZipArchive(std::string path) : path_(std::move(path))
{
    bytes_ = readFileBytes(path_);
    const Reader rd{bytes_, path_};
    if (bytes_.size() < 22) rd.bad(fmt::format("file too short ({} bytes) to be a zip archive", bytes_.size()));

    // End of central directory: search backwards (it may be followed by a comment ≤ 65535 bytes).
    uint64_t eocd = std::numeric_limits<uint64_t>::max();
    const uint64_t last = bytes_.size() - 22;
    const uint64_t first = last > 65535 ? last - 65535 : 0;
    for (uint64_t p = last + 1; p-- > first;)
    {
        if (rd.u32(p) == kSigEocd)
        {
            eocd = p;
            break;
        }
    }
    if (eocd == std::numeric_limits<uint64_t>::max())
    {
        const bool looks_zip = bytes_.size() >= 4 && rd.u32(0) == kSigLocal;
        rd.bad(looks_zip ? "end-of-central-directory record not found (file truncated?)"
                         : "not a zip archive (no end-of-central-directory record)");
    }
    uint64_t n_entries = rd.u16(eocd + 10);
    uint64_t cd_size = rd.u32(eocd + 12);
    uint64_t cd_offset = rd.u32(eocd + 16);
    if (rd.u16(eocd + 4) != 0 || rd.u16(eocd + 6) != 0) rd.bad("multi-disk archives are not supported");

    if (n_entries == 0xFFFF || cd_size == 0xFFFFFFFF || cd_offset == 0xFFFFFFFF)
    {
        if (eocd < 20 || rd.u32(eocd - 20) != kSigZip64Locator)
            rd.bad("ZIP64 values without a ZIP64 end-of-central-directory locator");
        const uint64_t z64 = rd.u64(eocd - 20 + 8);
        rd.need(z64, 56, "ZIP64 end-of-central-directory record");
        if (rd.u32(z64) != kSigZip64Eocd) rd.bad("bad ZIP64 end-of-central-directory signature");
        n_entries = rd.u64(z64 + 32);
        cd_size = rd.u64(z64 + 40);
        cd_offset = rd.u64(z64 + 48);
    }
    rd.need(cd_offset, cd_size, "central directory");

    uint64_t p = cd_offset;
    for (uint64_t i = 0; i < n_entries; ++i)
    {
        rd.need(p, 46, "central directory entry");
        if (rd.u32(p) != kSigCentral)
            rd.bad(fmt::format("bad central directory signature for entry {}", i));
        ZipEntry e;
        e.flags = rd.u16(p + 8);
        e.method = rd.u16(p + 10);
        e.crc32 = rd.u32(p + 16);
        e.compressed_size = rd.u32(p + 20);
        e.uncompressed_size = rd.u32(p + 24);
        const uint16_t name_len = rd.u16(p + 28);
        const uint16_t extra_len = rd.u16(p + 30);
        const uint16_t comment_len = rd.u16(p + 32);
        e.local_header_offset = rd.u32(p + 42);
        rd.need(p + 46, uint64_t{name_len} + extra_len + comment_len, "central directory entry");
        e.name.assign(bytes_.data() + p + 46, name_len);

        // ZIP64 extended information extra field (header id 0x0001).
        uint64_t x = p + 46 + name_len;
        const uint64_t x_end = x + extra_len;
        while (x + 4 <= x_end)
        {
            const uint16_t id = rd.u16(x);
            const uint16_t sz = rd.u16(x + 2);
            if (x + 4 + sz > x_end) rd.bad(fmt::format("extra field overruns entry '{}'", e.name));
            if (id == 0x0001)
            {
                uint64_t q = x + 4;
                const uint64_t q_end = q + sz;
                auto take = [&](uint64_t& field) {
                    if (q + 8 > q_end) rd.bad(fmt::format("short ZIP64 extra field in '{}'", e.name));
                    field = rd.u64(q);
                    q += 8;
                };
                if (e.uncompressed_size == 0xFFFFFFFF) take(e.uncompressed_size);
                if (e.compressed_size == 0xFFFFFFFF) take(e.compressed_size);
                if (e.local_header_offset == 0xFFFFFFFF) take(e.local_header_offset);
            }
            x += 4 + sz;
        }
        entries_.push_back(std::move(e));
        p += 46 + uint64_t{name_len} + extra_len + comment_len;
    }
}

const ZipEntry* ZipArchive::find(const std::string& name) const
{
    auto it = std::find_if(entries_.begin(), entries_.end(),
                           [&](const ZipEntry& e) { return e.name == name; });
    return it == entries_.end() ? nullptr : &*it;
}

std::string ZipArchive::extract(const ZipEntry& e) const
{
    const Reader rd{bytes_, path_};
    if (e.flags & 0x1) rd.bad(fmt::format("entry '{}' is encrypted", e.name));
    if (e.uncompressed_size > kMaxEntryBytes)
        rd.bad(fmt::format("entry '{}' is too large ({} bytes)", e.name, e.uncompressed_size));
    rd.need(e.local_header_offset, 30, "local file header");
    if (rd.u32(e.local_header_offset) != kSigLocal)
        rd.bad(fmt::format("bad local header signature for entry '{}'", e.name));
    const uint64_t data = e.local_header_offset + 30 + rd.u16(e.local_header_offset + 26) +
                          rd.u16(e.local_header_offset + 28);
    rd.need(data, e.compressed_size, "entry data");
    const char* src = bytes_.data() + data;

    std::string out;
    if (e.method == 0)
    {
        if (e.compressed_size != e.uncompressed_size)
            rd.bad(fmt::format("stored entry '{}' has compressed size {} != size {}", e.name,
                               e.compressed_size, e.uncompressed_size));
        out.assign(src, e.compressed_size);
    }
    else if (e.method == 8)
    {
        // Deflate expands at most 1032:1, so a size beyond that is a lie: refused before the
        // buffer is allocated (found by fuzz_npz: a 2 GiB claim from a few hundred bytes).
        if (e.uncompressed_size > e.compressed_size * kMaxDeflateRatio + 1024)
            rd.bad(fmt::format("entry '{}' claims {} bytes from {} compressed bytes (deflate expands at most "
                               "{}:1)",
                               e.name, e.uncompressed_size, e.compressed_size, kMaxDeflateRatio));
        out.resize(e.uncompressed_size);
        z_stream zs{};
        if (inflateInit2(&zs, -MAX_WBITS) != Z_OK) rd.bad("zlib initialisation failed");
        // Feed and drain in chunks of at most 1 GiB (uInt is 32-bit).
        uint64_t in_left = e.compressed_size, out_left = e.uncompressed_size;
        zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(src));
        zs.next_out = reinterpret_cast<Bytef*>(out.data());
        int ret = Z_OK;
        while (ret == Z_OK)
        {
            if (zs.avail_in == 0 && in_left > 0)
            {
                zs.avail_in = static_cast<uInt>(std::min<uint64_t>(in_left, 1u << 30));
                in_left -= zs.avail_in;
            }
            if (zs.avail_out == 0 && out_left > 0)
            {
                zs.avail_out = static_cast<uInt>(std::min<uint64_t>(out_left, 1u << 30));
                out_left -= zs.avail_out;
            }
            ret = inflate(&zs, Z_NO_FLUSH);
            if (ret == Z_BUF_ERROR && (zs.avail_in > 0 || in_left > 0) &&
                (zs.avail_out > 0 || out_left > 0))
                ret = Z_OK;  // progress still possible
        }
        const uint64_t produced = zs.total_out;
        const std::string zmsg = ret == Z_BUF_ERROR ? "unexpected end of data"
                                 : zs.msg           ? zs.msg
                                                    : "zlib error";
        inflateEnd(&zs);
        if (ret != Z_STREAM_END)
            rd.bad(fmt::format("cannot inflate entry '{}' ({}; data truncated or corrupt)", e.name,
                               zmsg));
        if (produced != e.uncompressed_size)
            rd.bad(fmt::format("entry '{}' inflated to {} bytes, expected {}", e.name, produced,
                               e.uncompressed_size));
    }
    else
    {
        rd.bad(fmt::format("entry '{}' uses unsupported compression method {} (only 0 = stored "
                           "and 8 = deflate)",
                           e.name, e.method));
    }
    uLong crc = crc32(0L, Z_NULL, 0);
    const char* q = out.data();
    uint64_t left = out.size();
    while (left > 0)
    {
        const uInt n = static_cast<uInt>(std::min<uint64_t>(left, 1u << 30));
        crc = crc32(crc, reinterpret_cast<const Bytef*>(q), n);
        q += n;
        left -= n;
    }
    if (static_cast<uint32_t>(crc) != e.crc32)
        rd.bad(fmt::format("CRC-32 mismatch in entry '{}' (file corrupt)", e.name));
    return out;
}

}  // namespace pndt::io::detail
