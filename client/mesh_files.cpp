#include "mesh_files.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "isocorr/util/sha256.h"

namespace isocorr::cli {

std::string mesh_file_label(const std::string& role, const std::string& path) {
  return (role.empty() ? "mesh file" : role + " mesh") + " '" + path + "'";
}

InputError mesh_file_error(const std::string& role, const std::string& path, const std::string& problem) {
  return InputError(mesh_file_label(role, path) + ": " + problem);
}

std::string read_mesh_file(const std::string& role, const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) throw mesh_file_error(role, path, "it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw mesh_file_error(role, path, std::string("cannot read it: ") + std::strerror(errno));
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) throw mesh_file_error(role, path, "cannot read it: read error");
  std::string content = std::move(bytes).str();
  if (content.empty()) throw mesh_file_error(role, path, "the mesh file is empty");
  return content;
}

LoadedMesh load_mesh_file(const std::string& role, const std::string& path, std::string* sha256) {
  const std::string bytes = read_mesh_file(role, path);
  if (sha256) *sha256 = sha256_hex(bytes);
  try {
    return parse_mesh(bytes, path);
  } catch (const InputError& e) {
    throw mesh_file_error(role, path, e.what());
  }
}

void check_matchable_file(const std::string& role, const std::string& path, const LoadedMesh& loaded,
                          const CleaningOptions& cleaning) {
  try {
    check_matchable(clean_mesh(loaded.mesh, cleaning));
  } catch (const InputError& e) {
    throw mesh_file_error(role, path, e.what());
  }
}

}  // namespace isocorr::cli
