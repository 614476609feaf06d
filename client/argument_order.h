// One order of positional arguments for every local command: the meshes first, source then
// target as the map runs, then the map (`match SOURCE TARGET`, `render SOURCE TARGET MAP`,
// `eval SOURCE TARGET MAP`). Commands whose order changed refuse the old one by name.
#pragma once

#include <string>

namespace isocorr::cli {

// True when the name ends in .off, .obj or .ply, in any case.
bool has_mesh_extension(const std::string& path);

// Throws InputError naming `usage` ("isocorr render SOURCE TARGET MAP") when the arguments
// look like the map-first order: `source` (the first positional) is no mesh by its
// extension and `map` (the last) is one. Looks at the names only, so it runs before any
// file is read.
void check_meshes_before_map(const std::string& usage, const std::string& source, const std::string& map);

}  // namespace isocorr::cli
