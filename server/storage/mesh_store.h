// Content-addressed mesh store under <data-dir>/meshes: the file bytes as uploaded
// (<sha256>.mesh) and what the parser found (<sha256>.json, sealed). A mesh exists once its
// .json is on disk; both are written durably, so an acknowledged upload survives a kill -9.
// The bytes take their final name only after the .json is written (until then they are
// <sha256>.mesh.pending), so a .mesh found without its .json at start is a mesh whose
// description was lost: it is quarantined and reported as DATA_LOSS, never deleted.
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

#include "storage/mesh_repository.h"
#include "storage/quarantine.h"

namespace isocorr::server {

class MeshStore;

// An upload into the data directory: bytes go to a temporary file while being hashed.
class DirectoryMeshUpload final : public MeshUpload {
 public:
  ~DirectoryMeshUpload() override;

 private:
  friend class MeshStore;
  DirectoryMeshUpload(MeshStore& store, std::string digest, std::string filename, std::filesystem::path temp);
  void keep(std::string_view bytes) override;
  std::string kept_bytes() override;
  MeshInfo store(const MeshInfo& info) override;

  MeshStore& store_;
  std::filesystem::path temp_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
};

class MeshStore final : public MeshRepository {
 public:
  MeshStore(const std::filesystem::path& data_dir, int64_t max_mesh_bytes);

  std::unique_ptr<MeshUpload> begin_upload(const std::string& digest, const std::string& filename,
                                           int64_t declared_size) override;
  std::optional<MeshInfo> describe(const std::string& digest) override;
  std::optional<MeshInfo> get(const std::string& digest) override;
  std::optional<MeshInfo> find_intact(const std::string& digest) override;
  std::vector<MeshInfo> list() override;  // unreadable descriptions are quarantined
  bool remove(const std::string& digest) override;
  StoredMesh read(const std::string& digest) override;
  int64_t max_mesh_bytes() const override { return max_mesh_bytes_; }

 private:
  friend class DirectoryMeshUpload;
  std::filesystem::path mesh_path(const std::string& digest) const { return dir_ / (digest + ".mesh"); }
  std::filesystem::path info_path(const std::string& digest) const { return dir_ / (digest + ".json"); }
  static constexpr const char* kPendingSuffix = ".mesh.pending";
  std::filesystem::path pending_path(const std::string& digest) const { return dir_ / (digest + kPendingSuffix); }

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
