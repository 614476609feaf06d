#include "isocorr/mesh/ply_properties.h"

#include <fstream>
#include <iterator>

#include "isocorr/util/error.h"
#include "mesh_formats.h"

namespace isocorr {

std::vector<double> read_ply_vertex_properties(const std::string& path, const std::vector<std::string>& names) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot read '" + path + "'");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  try {
    return mesh_formats::ply_vertex_properties(bytes, names);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
}

}  // namespace isocorr
