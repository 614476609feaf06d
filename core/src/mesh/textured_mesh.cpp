// Reading and writing meshes with corner attributes: the readers of mesh_io.cpp with the
// OBJ reader recording them, and the OBJ writer with them.
#include "isocorr/mesh/textured_mesh.h"

#include "isocorr/util/error.h"
#include "mesh_formats.h"
#include "text_scanning.h"

namespace isocorr {

namespace {

using mesh_formats::cat;

void check_face_list(const std::vector<std::array<int, 3>>& list, size_t faces, size_t entries, const char* what) {
  if (!list.empty() && list.size() != faces)
    throw InputError(cat("the corners' ", what, " indices list ", list.size(), " faces, the mesh has ", faces));
  for (size_t f = 0; f < list.size(); ++f)
    for (int index : list[f])
      if (index < -1 || index >= static_cast<long long>(entries))
        throw InputError(cat("face ", f, " refers to ", what, " ", index, " of ", entries));
}

}  // namespace

TexturedMesh parse_textured_mesh(const std::string& bytes, const std::string& name_hint) {
  TexturedMesh textured;
  textured.mesh = mesh_formats::parse_mesh_bytes(bytes, name_hint, &textured.corners).mesh;
  return textured;
}

TexturedMesh load_textured_mesh(const std::string& path) {
  TexturedMesh textured;
  textured.mesh = mesh_formats::load_mesh_file(path, &textured.corners).mesh;
  return textured;
}

void check_corner_attributes(const TriangleMesh& mesh, const CornerAttributes& corners) {
  const size_t faces = mesh.faces.size();
  check_face_list(corners.face_uvs, faces, corners.uvs.size(), "texture coordinate");
  check_face_list(corners.face_normals, faces, corners.normals.size(), "normal");
  if (!corners.face_materials.empty() && corners.face_materials.size() != faces)
    throw InputError(cat("the corners' materials list ", corners.face_materials.size(), " faces, the mesh has ", faces));
  for (size_t f = 0; f < corners.face_materials.size(); ++f)
    if (corners.face_materials[f] < -1 || corners.face_materials[f] >= static_cast<long long>(corners.materials.size()))
      throw InputError(cat("face ", f, " refers to material ", corners.face_materials[f], " of ", corners.materials.size()));
}

std::string textured_obj_text(const TexturedMesh& textured) {
  check_corner_attributes(textured.mesh, textured.corners);
  return mesh_formats::obj_text(textured.mesh, textured.corners);
}

void write_textured_obj(const std::string& path, const TexturedMesh& textured) {
  mesh_formats::write_text_file(path, textured_obj_text(textured));
}

}  // namespace isocorr
