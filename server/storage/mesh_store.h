// Content-addressed mesh store under <data-dir>/meshes: the file bytes as uploaded
// (<sha256>.mesh) and what the parser found (<sha256>.json). A mesh exists once its .json
// is on disk; both are written durably, so an acknowledged upload survives a kill -9.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "isocorr/util/sha256.h"

namespace isocorr::server {

struct MeshInfo {
  std::string digest;  // SHA-256, lower-case hex
  std::string filename;
  int64_t size_bytes = 0;
  std::string format;
  int vertex_count = 0;
  int face_count = 0;
  std::vector<std::string> notes;
  int64_t create_time_ms = 0;  // since the Unix epoch
};

class MeshStore;

// One upload in progress: bytes go to a temporary file while being hashed.
class MeshUpload {
 public:
  ~MeshUpload();
  // Throws ServiceError(kResourceExhausted) past the store's size limit.
  void append(std::string_view bytes);
  // Verifies the digest and the mesh, then stores it. Throws ServiceError
  // (kInvalidArgument) naming the problem.
  MeshInfo commit();

 private:
  friend class MeshStore;
  MeshUpload(MeshStore& store, std::string digest, std::string filename, std::filesystem::path temp);
  MeshStore& store_;
  std::string digest_, filename_;
  std::filesystem::path temp_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  Sha256 hasher_;
  int64_t received_ = 0;
};

class MeshStore {
 public:
  MeshStore(const std::filesystem::path& data_dir, int64_t max_mesh_bytes);

  // Validates the header (digest syntax, declared size against the limit).
  std::unique_ptr<MeshUpload> begin_upload(const std::string& digest, const std::string& filename,
                                           int64_t declared_size);
  std::optional<MeshInfo> get(const std::string& digest) const;
  std::vector<MeshInfo> list() const;  // by digest
  bool remove(const std::string& digest);
  // The stored file bytes; throws ServiceError(kNotFound).
  std::string read_bytes(const std::string& digest) const;
  int64_t max_mesh_bytes() const { return max_mesh_bytes_; }

 private:
  friend class MeshUpload;
  std::filesystem::path mesh_path(const std::string& digest) const { return dir_ / (digest + ".mesh"); }
  std::filesystem::path info_path(const std::string& digest) const { return dir_ / (digest + ".json"); }

  std::filesystem::path dir_, temp_dir_;
  int64_t max_mesh_bytes_;
  mutable std::mutex mutex_;  // serialises commits and deletes of the same names
};

}  // namespace isocorr::server
