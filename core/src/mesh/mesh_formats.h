// The per-format readers behind parse_mesh (mesh_io.cpp picks one). Mesh files come from
// users, so every malformed input becomes an InputError naming the problem, and header
// counts are checked against the bytes that follow before anything is allocated.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/textured_mesh.h"

namespace isocorr::mesh_formats {

// Each takes the file's bytes (any UTF-8 byte-order mark already removed).
LoadedMesh parse_off(std::string_view text);
// parse_obj also records the corner attributes into `corners` when given one; without, it
// ignores vt/vn references as it always has, so matching reads the same files as before.
LoadedMesh parse_obj(std::string_view text, CornerAttributes* corners = nullptr);
LoadedMesh parse_ply(std::string_view bytes);

// parse_mesh and load_mesh, with the OBJ reader recording corner attributes into `corners`
// when given one (the other formats leave it untouched).
LoadedMesh parse_mesh_bytes(const std::string& bytes, const std::string& name_hint, CornerAttributes* corners);
LoadedMesh load_mesh_file(const std::string& path, CornerAttributes* corners);

// Writes `text` to `path`, replacing the file; InputError if it cannot.
void write_text_file(const std::string& path, const std::string& text);

// The text of a mesh in each text format, coordinates in the shortest text that reads back
// as the same double.
std::string off_text(const TriangleMesh& mesh);
std::string obj_text(const TriangleMesh& mesh);
// OBJ with corner attributes (which must fit the mesh: check_corner_attributes).
std::string obj_text(const TriangleMesh& mesh, const CornerAttributes& corners);

// The named scalar properties of a PLY file's vertices, row by row (ply_properties.h).
std::vector<double> ply_vertex_properties(std::string_view bytes, const std::vector<std::string>& names);

}  // namespace isocorr::mesh_formats
