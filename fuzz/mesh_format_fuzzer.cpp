// parse_mesh on arbitrary bytes with a file name of one format (ISOCORR_FUZZ_NAME_HINT), so
// that format's reader sees the bytes even when their start does not name it.
#include <cmath>
#include <cstdint>
#include <string>

#include "fuzz_checks.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/util/error.h"

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
  } catch (const isocorr::InputError&) {
    // Rejecting malformed bytes is the reader's job; anything else thrown is a defect.
  }
  return 0;
}
