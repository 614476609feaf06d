// Meshes in the shared PostgreSQL database (table isocorr_meshes): the file's bytes and the
// sealed description, one row per digest, so that any replica serves any mesh. Checked
// like the local store: the description's seal, its digest and size, and (when the bytes
// are read) their SHA-256 against the name. A corrupted row is kept with the reason in
// set_aside and answers DATA_LOSS until the same file is uploaded again.
#pragma once

#include "postgres/pg_database.h"
#include "storage/mesh_repository.h"

namespace isocorr::server {

class PgMeshStore final : public MeshRepository {
 public:
  PgMeshStore(PgDatabase& database, int64_t max_mesh_bytes) : database_(database), max_mesh_bytes_(max_mesh_bytes) {}

  std::unique_ptr<MeshUpload> begin_upload(const std::string& digest, const std::string& filename,
                                           int64_t declared_size) override;
  std::optional<MeshInfo> describe(const std::string& digest) override;
  std::optional<MeshInfo> get(const std::string& digest) override;
  std::optional<MeshInfo> find_intact(const std::string& digest) override;
  std::vector<MeshInfo> list() override;
  bool remove(const std::string& digest) override;
  StoredMesh read(const std::string& digest) override;
  int64_t max_mesh_bytes() const override { return max_mesh_bytes_; }

  enum class Found { kAbsent, kIntact, kSetAside };
  struct Lookup {
    Found found = Found::kAbsent;
    MeshInfo info;
    std::string bytes;  // when asked for
  };
  // The row checked; a corrupted one is set aside (under a row lock, so a concurrent repair
  // is not undone). `lock` takes the row lock from the start (the upload's commit).
  Lookup checked(pqxx::work& txn, const std::string& digest, bool with_bytes, bool lock);

 private:
  Lookup checked(const std::string& digest, bool with_bytes);

  PgDatabase& database_;
  const int64_t max_mesh_bytes_;
};

}  // namespace isocorr::server
