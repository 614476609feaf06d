// parse_mesh and parse_textured_mesh on arbitrary bytes with a file name of one format
// (ISOCORR_FUZZ_NAME_HINT), so that format's reader sees the bytes even when their start
// does not name it.
#include <cmath>
#include <cstdint>
#include <string>

#include "fuzz_checks.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/textured_mesh.h"
#include "isocorr/util/error.h"

namespace {

bool same(const isocorr::CornerAttributes& a, const isocorr::CornerAttributes& b) {
  return a.uvs == b.uvs && a.face_uvs == b.face_uvs && a.normals == b.normals && a.face_normals == b.face_normals &&
         a.material_library == b.material_library && a.materials == b.materials &&
         a.face_materials == b.face_materials;
}

// The reader with corner attributes reads the same mesh, attributes that fit it, and its
// own written text back unchanged.
void check_textured(const std::string& bytes, const isocorr::TriangleMesh& mesh) {
  isocorr::TexturedMesh textured;
  try {
    textured = isocorr::parse_textured_mesh(bytes, ISOCORR_FUZZ_NAME_HINT);
  } catch (const isocorr::InputError&) {
    return;  // stricter than parse_mesh about vt/vn references, by design
  }
  ISOCORR_FUZZ_CHECK(textured.mesh.faces == mesh.faces && textured.mesh.vertices == mesh.vertices);
  for (const auto& uv : textured.corners.uvs) ISOCORR_FUZZ_CHECK(std::isfinite(uv[0]) && std::isfinite(uv[1]));
  for (const auto& n : textured.corners.normals) ISOCORR_FUZZ_CHECK(n.allFinite());
  const std::string text = isocorr::textured_obj_text(textured);  // throws InputError if they do not fit
  const isocorr::TexturedMesh again = isocorr::parse_textured_mesh(text, "again.obj");
  ISOCORR_FUZZ_CHECK(again.mesh.faces == textured.mesh.faces && again.mesh.vertices == textured.mesh.vertices);
  ISOCORR_FUZZ_CHECK(same(again.corners, textured.corners));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const isocorr::LoadedMesh loaded = isocorr::parse_mesh(bytes, ISOCORR_FUZZ_NAME_HINT);
    // Promised by parse_mesh: at least one face, indices in range, finite coordinates.
    const isocorr::TriangleMesh& mesh = loaded.mesh;
    ISOCORR_FUZZ_CHECK(mesh.num_faces() > 0);
    for (const auto& face : mesh.faces)
      for (int v : face) ISOCORR_FUZZ_CHECK(v >= 0 && v < mesh.num_vertices());
    for (const auto& p : mesh.vertices) ISOCORR_FUZZ_CHECK(p.allFinite());
    check_textured(bytes, mesh);
  } catch (const isocorr::InputError&) {
    // Rejecting malformed bytes is the reader's job; anything else thrown is a defect.
  }
  return 0;
}
