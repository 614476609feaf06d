// A mesh with what OBJ files attach to face corners: texture coordinates, normals and
// materials. Per corner, so a vertex on a UV seam keeps a different UV in each face.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

// Attributes of the triangle corners of a mesh, faces in the mesh's order (polygons split
// into fans as load_mesh splits them). Each per-face list is either empty (no corner of the
// file has that attribute) or holds one entry per face; -1 marks a corner without one.
struct CornerAttributes {
  std::vector<std::array<double, 2>> uvs;       // the file's vt list, in order (a third value is dropped)
  std::vector<std::array<int, 3>> face_uvs;     // per face: its corners' indices into uvs
  std::vector<Vec3> normals;                    // the file's vn list, in order, as written (not normalised)
  std::vector<std::array<int, 3>> face_normals;  // per face: its corners' indices into normals
  std::string material_library;                 // the mtllib line's names, verbatim ("" if none)
  std::vector<std::string> materials;           // usemtl names, in the order faces first use them
  std::vector<int> face_materials;              // per face: index into materials in effect, -1 none
};

struct TexturedMesh {
  TriangleMesh mesh;
  CornerAttributes corners;
};

// parse_mesh / load_mesh, plus the corner attributes of an OBJ file (other formats: none).
// `mesh` is exactly what parse_mesh gives for the same bytes. Beyond parse_mesh's checks,
// malformed corner references (anything but v, v/t, v//n, v/t/n), texture-coordinate or
// normal indices out of range and non-finite vt/vn values throw InputError naming the line.
TexturedMesh parse_textured_mesh(const std::string& bytes, const std::string& name_hint);
TexturedMesh load_textured_mesh(const std::string& path);

// Throws InputError unless every per-face list is empty or one per face of `mesh` and
// every index is -1 or within its list.
void check_corner_attributes(const TriangleMesh& mesh, const CornerAttributes& corners);

// OBJ text: mtllib, v, vt, vn, then the faces as "f v/t/n" (v/t, v//n or v where a corner
// lacks one) with a usemtl line where the material changes. Coordinates exact; reading it
// back gives the same mesh and attributes (materials listed only if a face uses them).
std::string textured_obj_text(const TexturedMesh& textured);
// Writes textured_obj_text to `path`; InputError if the attributes do not fit the mesh or
// the file cannot be written.
void write_textured_obj(const std::string& path, const TexturedMesh& textured);

}  // namespace isocorr
