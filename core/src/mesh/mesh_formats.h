// The per-format readers behind parse_mesh (mesh_io.cpp picks one). Mesh files come from
// users, so every malformed input becomes an InputError naming the problem, and header
// counts are checked against the bytes that follow before anything is allocated.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "isocorr/mesh/mesh_io.h"

namespace isocorr::mesh_formats {

// Each takes the file's bytes (any UTF-8 byte-order mark already removed).
LoadedMesh parse_off(std::string_view text);
LoadedMesh parse_obj(std::string_view text);
LoadedMesh parse_ply(std::string_view bytes);

// The text of a mesh in each text format, coordinates in the shortest text that reads back
// as the same double.
std::string off_text(const TriangleMesh& mesh);
std::string obj_text(const TriangleMesh& mesh);

// The named scalar properties of a PLY file's vertices, row by row (ply_properties.h).
std::vector<double> ply_vertex_properties(std::string_view bytes, const std::vector<std::string>& names);

}  // namespace isocorr::mesh_formats
