// Which maps pndt-eval scores: one .pndt.gz, or every map a pndt-map output folder lists
// in its index.json (only complete maps are listed there).
#pragma once

#include <string>
#include <vector>

namespace pndt::evalapp
{
/// Paths of the map files; throws InputError naming the file or folder when it is missing,
/// the index is not a JSON array of {"file": ...}, or a listed map is absent.
std::vector<std::string> mapFiles(const std::string& map_or_folder);
}  // namespace pndt::evalapp
