// Content-addressed mesh store under <data-dir>/meshes: the file bytes as uploaded
// (<sha256>.mesh) and what the parser found (<sha256>.json, sealed). A mesh exists once its
// .json is on disk; both are written durably, so an acknowledged upload survives a kill -9.
//
// Stored bytes are checked against their name whenever they are read. A mesh found
// corrupted is moved to quarantine/meshes/ and reported as ServiceError(kDataLoss) from
// then on, until an upload of the right bytes stores it again (the repair).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "isocorr/util/sha256.h"
#include "storage/quarantine.h"

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
  // (kInvalidArgument) naming the problem, or (kResourceExhausted) when the disk is full;
  // a failed commit leaves no file behind.
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
  // nullopt when there is no such mesh; ServiceError(kDataLoss) when it is corrupted or
  // was quarantined and not uploaded again.
  // describe: the description only (and the file's size); get: also hashes the bytes.
  std::optional<MeshInfo> describe(const std::string& digest);
  std::optional<MeshInfo> get(const std::string& digest);
  // As get, but a corrupted or quarantined mesh counts as absent: the upload path, where
  // the right bytes repair it.
  std::optional<MeshInfo> find_intact(const std::string& digest);
  std::vector<MeshInfo> list();  // by digest; descriptions only, unreadable ones quarantined
  bool remove(const std::string& digest);

  struct StoredMesh {
    MeshInfo info;
    std::string bytes;  // checked against the digest
  };
  // Throws ServiceError(kNotFound, kDataLoss).
  StoredMesh read(const std::string& digest);
  int64_t max_mesh_bytes() const { return max_mesh_bytes_; }

 private:
  friend class MeshUpload;
  std::filesystem::path mesh_path(const std::string& digest) const { return dir_ / (digest + ".mesh"); }
  std::filesystem::path info_path(const std::string& digest) const { return dir_ / (digest + ".json"); }

  enum class Found { kAbsent, kIntact, kCorrupted, kQuarantined };
  struct Lookup {
    Found found = Found::kAbsent;
    MeshInfo info;
    std::string bytes;    // when asked for
    std::string problem;  // when kCorrupted
  };
  Lookup lookup(const std::string& digest, bool with_bytes) const;
  // Looks again under the lock (a concurrent upload may have repaired it), then moves a
  // still corrupted mesh to quarantine. Returns the final lookup.
  Lookup quarantine_if_corrupted(const std::string& digest, bool with_bytes);
  // Lookup with corruption handled: kIntact, kAbsent or kQuarantined only.
  Lookup checked(const std::string& digest, bool with_bytes);
  void remove_leftovers();

  std::filesystem::path dir_, temp_dir_;
  Quarantine quarantine_;
  int64_t max_mesh_bytes_;
  mutable std::mutex mutex_;  // serialises commits and deletes of the same names
};

}  // namespace isocorr::server
