// What the server asks of the place its meshes live, whichever it is: the local data
// directory (MeshStore, the default) or a database shared by several replicas
// (PgMeshStore). Both name a mesh by the SHA-256 of its bytes, check the bytes against
// that name whenever they are read, and answer ServiceError(kDataLoss) for a mesh found
// corrupted until the same file is uploaded again.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

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

nlohmann::json mesh_info_to_json(const MeshInfo& info);
MeshInfo mesh_info_from_json(const nlohmann::json& j);  // throws on a missing or mistyped field

// Said when a stored mesh is found corrupted, and every time it is asked for afterwards.
std::string corrupted_mesh_message(const std::string& digest);

// One upload in progress: its bytes are counted and hashed here while the store keeps them.
class MeshUpload {
 public:
  virtual ~MeshUpload() = default;
  // Throws ServiceError(kResourceExhausted) past the store's size limit.
  void append(std::string_view bytes);
  // Verifies the digest and the mesh, then stores it. Throws ServiceError
  // (kInvalidArgument) naming the problem, or (kResourceExhausted) when the store is full;
  // a failed commit leaves nothing behind.
  MeshInfo commit();

 protected:
  MeshUpload(std::string digest, std::string filename, int64_t max_bytes);
  virtual void keep(std::string_view bytes) = 0;
  // Every byte kept, once the last has arrived.
  virtual std::string kept_bytes() = 0;
  // Stores the checked mesh; returns what is stored (an intact copy stored concurrently wins).
  virtual MeshInfo store(const MeshInfo& info) = 0;

  const std::string digest_, filename_;

 private:
  const int64_t max_bytes_;
  Sha256 hasher_;
  int64_t received_ = 0;
};

class MeshRepository {
 public:
  struct StoredMesh {
    MeshInfo info;
    std::string bytes;  // checked against the digest
  };

  virtual ~MeshRepository() = default;
  // Validates the header (digest syntax, declared size against the limit).
  virtual std::unique_ptr<MeshUpload> begin_upload(const std::string& digest, const std::string& filename,
                                                   int64_t declared_size) = 0;
  // nullopt when there is no such mesh; ServiceError(kDataLoss) when it is corrupted or
  // was set aside and not uploaded again.
  // describe: the description only (and the stored size); get: also hashes the bytes.
  virtual std::optional<MeshInfo> describe(const std::string& digest) = 0;
  virtual std::optional<MeshInfo> get(const std::string& digest) = 0;
  // As get, but a corrupted or set-aside mesh counts as absent: the upload path, where
  // the right bytes repair it.
  virtual std::optional<MeshInfo> find_intact(const std::string& digest) = 0;
  virtual std::vector<MeshInfo> list() = 0;  // by digest; descriptions only, corrupted ones set aside
  virtual bool remove(const std::string& digest) = 0;
  // Throws ServiceError(kNotFound, kDataLoss).
  virtual StoredMesh read(const std::string& digest) = 0;
  virtual int64_t max_mesh_bytes() const = 0;

 protected:
  // The checks of begin_upload that do not depend on where meshes live.
  void check_upload_header(const std::string& digest, int64_t declared_size) const;
};

}  // namespace isocorr::server
