// An MRPT archive that passes every byte to another archive and keeps the CRC-32 of
// them: the map's payload carries its own checksum (format version 6), because gzip's
// CRC only guards the compressed file, and a payload damaged and then recompressed
// (or stored plain) would otherwise load as a map with voxels in the wrong place.
#pragma once

#include <mrpt/serialization/CArchive.h>
#include <zlib.h>

#include <algorithm>
#include <cstdint>

namespace pndt
{
class CrcArchive : public mrpt::serialization::CArchive
{
   public:
    explicit CrcArchive(mrpt::serialization::CArchive& inner) : inner_(inner) {}
    /// CRC-32 (zlib's) of every byte read or written through this archive so far.
    uint32_t crc() const { return uint32_t(crc_); }

   protected:
    size_t write(const void* buf, size_t len) override
    {
        inner_.WriteBuffer(buf, len);
        update(buf, len);
        return len;
    }
    size_t read(void* buf, size_t len) override
    {
        const size_t n = inner_.ReadBuffer(buf, len);
        update(buf, n);
        return n;
    }

   private:
    void update(const void* buf, size_t len)
    {
        auto* p = static_cast<const Bytef*>(buf);
        while (len > 0)  // zlib counts in 32 bits
        {
            const uInt k = uInt(std::min<size_t>(len, 1u << 30));
            crc_ = crc32(crc_, p, k);
            p += k;
            len -= k;
        }
    }
    mrpt::serialization::CArchive& inner_;
    uLong crc_ = crc32(0L, Z_NULL, 0);
};
}  // namespace pndt
