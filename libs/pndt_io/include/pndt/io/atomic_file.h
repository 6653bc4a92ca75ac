// Atomic file writes for every writer of the project: the bytes go to a temporary file in the
// target's folder, which is then renamed over the target (readers never see half a file).
#pragma once

#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace pndt::io
{
/// A file could not be written; the message names the file and the reason.
struct WriteError : std::runtime_error
{
    using std::runtime_error::runtime_error;
};

/// Writes `bytes` to `path` atomically (temp file + fsync + rename). The folder must exist.
/// Throws WriteError naming `path`.
void writeFileAtomically(const std::string& path, std::string_view bytes);

/// For writers that need a path (image codecs, gzip streams): `write(tmp)` fills a
/// temporary file in the target's folder, which is then synced and renamed over
/// `path`; on any failure the temporary is removed and the error rethrown.
void writeFileAtomically(const std::string& path, const std::function<void(const std::string& tmp_path)>& write);

/// Closes a stream that filled the temporary of `path`: throws WriteError naming `path`
/// and the reason (errno of the failing write, e.g. "No space left on device") if a write
/// or the close failed. Without it a stream closed by its destructor drops the error, and
/// the short file would be renamed into place.
void closeWrittenStream(std::ofstream& f, const std::string& path);

/// Creates `dir` and its parents if missing. Throws WriteError naming `dir`.
void ensureDirectory(const std::string& dir);

}  // namespace pndt::io
