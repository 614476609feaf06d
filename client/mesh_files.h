// Mesh files as the CLI reads them: every refusal names the file and, where a command takes
// two meshes, whether it is the source or the target ("source mesh 'a.off': ...").
#pragma once

#include <string>

#include "isocorr/mesh/mesh_cleaning.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/util/error.h"

namespace isocorr::cli {

// "source mesh 'a.off'"; "mesh file 'a.off'" when `role` is empty.
std::string mesh_file_label(const std::string& role, const std::string& path);

// InputError("<label>: <problem>").
InputError mesh_file_error(const std::string& role, const std::string& path, const std::string& problem);

// The file's bytes. Throws mesh_file_error when it cannot be read or is empty.
std::string read_mesh_file(const std::string& role, const std::string& path);

// Reads and parses the file; every InputError names the file and its role. With `sha256`,
// also sets it to the hex SHA-256 of the file's bytes.
LoadedMesh load_mesh_file(const std::string& role, const std::string& path, std::string* sha256 = nullptr);

// Throws mesh_file_error unless `loaded` can be matched with `cleaning` (what a match checks
// first, without saying which mesh failed).
void check_matchable_file(const std::string& role, const std::string& path, const LoadedMesh& loaded,
                          const CleaningOptions& cleaning);

}  // namespace isocorr::cli
