#include "argument_order.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "isocorr/util/error.h"

namespace isocorr::cli {

bool has_mesh_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".off" || extension == ".obj" || extension == ".ply";
}

void check_meshes_before_map(const std::string& usage, const std::string& source, const std::string& map) {
  if (has_mesh_extension(source) || !has_mesh_extension(map)) return;
  throw InputError("the order is `" + usage + "`, the meshes first in the map's direction, then the map; '" +
                   source + "' looks like a map and '" + map + "' like a mesh");
}

}  // namespace isocorr::cli
