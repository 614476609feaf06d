// What the server does with an uploaded mesh before accepting it (MeshUpload::commit):
// parse, clean with the default options, check that it can be matched.
#include <cstdint>
#include <string>

#include "fuzz_checks.h"
#include "isocorr/mesh/mesh_cleaning.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const isocorr::LoadedMesh loaded = isocorr::parse_mesh(bytes, "upload");
    const isocorr::CleanMesh clean = isocorr::clean_mesh(loaded.mesh);
    isocorr::check_matchable(clean);
    // The bridge between numberings must cover both meshes with valid vertices.
    const int input_vertices = loaded.mesh.num_vertices(), clean_vertices = clean.mesh.num_vertices();
    ISOCORR_FUZZ_CHECK(static_cast<int>(clean.input_to_clean.size()) == input_vertices);
    ISOCORR_FUZZ_CHECK(static_cast<int>(clean.clean_to_input.size()) == clean_vertices);
    for (int v : clean.input_to_clean) ISOCORR_FUZZ_CHECK(v >= 0 && v < clean_vertices);
    for (int v : clean.clean_to_input) ISOCORR_FUZZ_CHECK(v >= 0 && v < input_vertices);
    // Every accepted mesh is computed on in the normalised range, whatever its file's scale.
    for (const auto& p : clean.mesh.vertices) ISOCORR_FUZZ_CHECK(p.allFinite() && p.cwiseAbs().maxCoeff() <= 3.0);
    for (const auto& face : clean.mesh.faces)
      for (int v : face) ISOCORR_FUZZ_CHECK(v >= 0 && v < clean_vertices);
  } catch (const isocorr::InputError&) {
  }
  return 0;
}
