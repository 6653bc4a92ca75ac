// Atomic file writes for every generator output, on top of pndt::io's
// writeFileAtomically (temporary in the same folder, fsync, rename): this adds the
// parent folders and a streaming producer. Every failure throws std::runtime_error
// whose message names the file.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace pndt::data
{
void writeFileAtomic(const std::string& path, const std::string& bytes);
/// `fill` streams the content; an exception from it removes the temporary and propagates.
void writeFileAtomic(const std::string& path, const std::function<void(std::ostream&)>& fill);

}  // namespace pndt::data
