#include "isocorr/mesh/ply_properties.h"

#include "isocorr/util/error.h"
#include "isocorr/util/file_bytes.h"
#include "mesh_formats.h"

namespace isocorr {

std::vector<double> read_ply_vertex_properties(const std::string& path, const std::vector<std::string>& names) {
  const std::string bytes = read_file_bytes(path, "PLY file");
  try {
    return mesh_formats::ply_vertex_properties(bytes, names);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
}

}  // namespace isocorr
