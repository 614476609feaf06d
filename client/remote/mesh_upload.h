// Puts a local mesh file on the server under its SHA-256, unless the server has it.
#pragma once

#include <string>

#include "remote/connection.h"

namespace isocorr::cli {

struct UploadOutcome {
  v1::Mesh mesh;
  bool uploaded = false;  // false: the server already had these bytes
};

// Asks GetMesh first, so a mesh the server has costs one small call; otherwise streams
// the file in 1 MiB chunks. Throws RpcError or InputError (unreadable or empty file); both
// name the file as "<role> mesh 'path'" ("source", "target"; "mesh file 'path'" when empty).
UploadOutcome ensure_uploaded(Connection& connection, const std::string& path, const std::string& role = "");

}  // namespace isocorr::cli
