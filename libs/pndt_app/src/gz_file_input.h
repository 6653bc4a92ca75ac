// A rawlog file read through zlib (gzip or plain), which, unlike MRPT's
// CFileGZInputStream (whose getPosition() is the decompressed offset), also
// tells how far into the compressed file it is: progress bars need both.
#pragma once

#include <mrpt/io/CStream.h>

#include <string>

namespace pndt::app
{
class GzFileInput : public mrpt::io::CStream
{
   public:
    /// Throws std::runtime_error naming the file if it cannot be opened.
    explicit GzFileInput(const std::string& path);
    ~GzFileInput() override;
    GzFileInput(const GzFileInput&) = delete;
    GzFileInput& operator=(const GzFileInput&) = delete;

    /// Decompressed bytes; throws on corrupt or cut gzip data (zlib's message).
    size_t Read(void* buffer, size_t count) override;
    size_t Write(const void*, size_t) override;
    uint64_t Seek(int64_t, CStream::TSeekOrigin) override;
    /// Size of the file on disk (compressed bytes).
    uint64_t getTotalBytesCount() const override { return file_size_; }
    /// Decompressed bytes read so far.
    uint64_t getPosition() const override { return position_; }
    /// Compressed bytes consumed so far (zlib reads ahead by at most its buffer).
    uint64_t compressedPosition() const;

   private:
    std::string path_;
    void* gz_ = nullptr;  ///< gzFile, kept opaque so zlib.h stays out of the header
    uint64_t file_size_ = 0, position_ = 0;
};
}  // namespace pndt::app
