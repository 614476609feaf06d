// Per-vertex properties of a PLY file beyond its positions: vertex colours (red, green,
// blue), skin weights, scalar fields, as the attributes `isocorr transfer` carries.
#pragma once

#include <string>
#include <vector>

namespace isocorr {

// The properties named, one row per vertex in the file's numbering, row by row. Throws
// InputError naming the file and a property the vertices lack (with those they have), or
// what is wrong with the file.
std::vector<double> read_ply_vertex_properties(const std::string& path, const std::vector<std::string>& names);

}  // namespace isocorr
