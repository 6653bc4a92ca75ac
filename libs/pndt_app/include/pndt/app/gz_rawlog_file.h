// One rawlog file written straight to its path through zlib, each object followed by a
// sync flush: the file on disk is always a valid rawlog up to its last complete object, so
// a crash or a full disk leaves a truncated file whose complete objects MRPT's tools and
// pndt-map read back. Used by maps.rawlog's writer and pndt-live's recording.
//
// Not thread-safe: one thread writes (the owner's writer thread).
#pragma once

#include <mrpt/serialization/CSerializable.h>
#include <pndt/io/atomic_file.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pndt::app
{
class GzRawlogFile
{
   public:
    /// Creates (truncates) `path`; gzip level 0..9. Throws io::WriteError naming the file
    /// and the reason.
    GzRawlogFile(std::string path, int compression);
    /// Closes the file if still open, swallowing errors (call close() to see them).
    ~GzRawlogFile();
    GzRawlogFile(const GzRawlogFile&) = delete;
    GzRawlogFile& operator=(const GzRawlogFile&) = delete;

    /// Serialises `obj` and flushes it to the file. Throws io::WriteError ("cannot write
    /// PATH: No space left on device", ...); the file then ends at the last object that
    /// was complete before this one.
    void write(const mrpt::serialization::CSerializable& obj);
    /// Writes the gzip trailer. Throws io::WriteError.
    void close();

    const std::string& path() const { return path_; }
    /// Compressed bytes on disk so far (with the trailer once closed).
    uint64_t bytes() const { return bytes_; }

   private:
    class Sink;
    std::string path_;
    void* gz_ = nullptr;  ///< gzFile, opaque to keep zlib.h out of the header
    std::unique_ptr<Sink> sink_;
    uint64_t bytes_ = 0;
};

/// File k of a rawlog cut into files: maps.rawlog -> maps-0000.rawlog, maps-0001.rawlog, ...
/// (the numbers sort in time order as text up to 9999).
std::string numberedRawlogPath(const std::string& path, size_t k);
/// The files numbered after `path` that exist (maps-0000.rawlog, maps-0001.rawlog, ...), sorted.
std::vector<std::string> numberedRawlogsOf(const std::string& path);
/// Whether `a` and `b` can name one file once numbered: the same folder (after following
/// links and "..") and the same name, or one's name numbered after the other's
/// (maps.rawlog, maps-0003.rawlog). An input or a recording must never be such a file of
/// a run's own output, which is truncated when the run writes it.
bool sameRawlogFamily(const std::string& a, const std::string& b);

}  // namespace pndt::app
