// Reading meshes from OFF (also NOFF/COFF), OBJ and PLY (ASCII and binary), and writing PLY.
#pragma once

#include <string>
#include <vector>

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

// A mesh as found in the file: vertex numbering is the file's. Polygons with more than
// three corners are split into fans; every such repair is described in `notes`.
struct LoadedMesh {
  TriangleMesh mesh;
  std::string format;               // "off", "obj", "ply-ascii", "ply-binary-le", ...
  std::vector<std::string> notes;   // human-readable remarks about what was repaired
};

// Reading a mesh file and cleaning it (clean_mesh) take at most this many bytes of memory per
// byte of the file: the readers keep no list of a polygon's corners and refuse more than 16
// triangles per vertex, and cleaning sorts four-byte face and edge numbers. The worst file we
// could make (a few vertices' polygons repeated, 11 MB) took 9.5. An upload budget counts it.
inline constexpr int kReadingPeakPerFileByte = 16;

// Parses a mesh from memory; `name_hint` (a file name) picks the format by extension when
// the content does not reveal it. Throws InputError naming the problem for anything
// malformed: truncated data, impossible header counts, NaN/inf coordinates, out-of-range
// indices, no faces. Never allocates more than the content can justify.
LoadedMesh parse_mesh(const std::string& bytes, const std::string& name_hint);

// Reads a file and parses it (throws InputError if it cannot be read).
LoadedMesh load_mesh(const std::string& path);

// Writes `mesh` in the format its name ends with: .off or .obj (text, coordinates exact) or
// .ply (binary, float coordinates, as write_ply). Throws InputError for another extension
// or a file that cannot be written.
void write_mesh(const std::string& path, const TriangleMesh& mesh);

// Writes a binary little-endian PLY with optional per-vertex RGB colours (empty = none).
void write_ply(const std::string& path, const TriangleMesh& mesh,
               const std::vector<std::array<unsigned char, 3>>& colours = {});

}  // namespace isocorr
