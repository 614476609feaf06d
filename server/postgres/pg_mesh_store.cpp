#include "postgres/pg_mesh_store.h"

#include <spdlog/spdlog.h>

#include "service_error.h"
#include "storage/sealed_json.h"

namespace isocorr::server {
using Kind = ServiceError::Kind;

namespace {

// The upload's bytes are kept in memory (the upload budget bounds them) until the commit
// writes them in one transaction.
class PgMeshUpload final : public MeshUpload {
 public:
  PgMeshUpload(PgMeshStore& store, PgDatabase& database, std::string digest, std::string filename, int64_t max_bytes)
      : MeshUpload(std::move(digest), std::move(filename), max_bytes), store_(store), database_(database) {}

 private:
  void keep(std::string_view bytes) override { bytes_.append(bytes); }
  std::string kept_bytes() override { return bytes_; }
  MeshInfo store(const MeshInfo& info) override {
    return database_.transaction([&](pqxx::work& txn) {
      // A concurrent upload won; a corrupted row is replaced (the repair).
      const PgMeshStore::Lookup existing = store_.checked(txn, digest_, /*with_bytes=*/true, /*lock=*/true);
      if (existing.found == PgMeshStore::Found::kIntact) return existing.info;
      txn.exec_params(
          "INSERT INTO isocorr_meshes (digest, description, bytes, set_aside) VALUES ($1, $2, $3, NULL) "
          "ON CONFLICT (digest) DO UPDATE SET description = EXCLUDED.description, bytes = EXCLUDED.bytes, "
          "set_aside = NULL",
          digest_, seal_json(mesh_info_to_json(info)), pqxx::binarystring(bytes_.data(), bytes_.size()));
      if (existing.found == PgMeshStore::Found::kSetAside)
        spdlog::info("storage: mesh {} repaired by a new upload", digest_);
      return info;
    });
  }

  PgMeshStore& store_;
  PgDatabase& database_;
  std::string bytes_;
};

// What is wrong with a stored row, or empty.
std::string problem_of(const std::string& digest, const pqxx::row& row, bool with_bytes, MeshInfo& info,
                       std::string& bytes) {
  try {
    info = mesh_info_from_json(unseal_json(row["description"].as<std::string>()));
  } catch (const std::exception& e) {
    return std::string("unreadable description: ") + e.what();
  }
  if (info.digest != digest) return "its description names another mesh";
  const int64_t size = row["size"].as<int64_t>();
  if (size != info.size_bytes)
    return "its size is " + std::to_string(size) + " bytes, not " + std::to_string(info.size_bytes);
  if (with_bytes) {
    bytes = pqxx::binarystring(row["bytes"]).str();
    if (sha256_hex(bytes) != digest) return "its bytes no longer hash to its name";
  }
  return "";
}

}  // namespace

std::unique_ptr<MeshUpload> PgMeshStore::begin_upload(const std::string& digest, const std::string& filename,
                                                      int64_t declared_size) {
  check_upload_header(digest, declared_size);
  return std::make_unique<PgMeshUpload>(*this, database_, digest, filename, max_mesh_bytes_);
}

PgMeshStore::Lookup PgMeshStore::checked(pqxx::work& txn, const std::string& digest, bool with_bytes, bool lock) {
  Lookup result;
  if (!is_sha256_hex(digest)) return result;
  const std::string query = std::string("SELECT description, octet_length(bytes) AS size, set_aside") +
                            (with_bytes ? ", bytes" : "") + " FROM isocorr_meshes WHERE digest = $1" +
                            (lock ? " FOR UPDATE" : "");
  const pqxx::result rows = txn.exec_params(query, digest);
  if (rows.empty()) return result;
  if (!rows[0]["set_aside"].is_null()) {
    result.found = Found::kSetAside;
    return result;
  }
  const std::string problem = problem_of(digest, rows[0], with_bytes, result.info, result.bytes);
  if (problem.empty()) {
    result.found = Found::kIntact;
    return result;
  }
  if (!lock) return checked(txn, digest, with_bytes, /*lock=*/true);  // look again under the row lock
  txn.exec_params("UPDATE isocorr_meshes SET set_aside = $2 WHERE digest = $1", digest, problem);
  spdlog::error("storage: mesh {} set aside in the database: {}", digest, problem);
  return Lookup{Found::kSetAside, {}, {}};
}

PgMeshStore::Lookup PgMeshStore::checked(const std::string& digest, bool with_bytes) {
  return database_.transaction(
      [&](pqxx::work& txn) { return checked(txn, digest, with_bytes, /*lock=*/false); });
}

std::optional<MeshInfo> PgMeshStore::describe(const std::string& digest) {
  Lookup result = checked(digest, /*with_bytes=*/false);
  if (result.found == Found::kSetAside) throw ServiceError(Kind::kDataLoss, corrupted_mesh_message(digest));
  if (result.found == Found::kAbsent) return std::nullopt;
  return std::move(result.info);
}

std::optional<MeshInfo> PgMeshStore::get(const std::string& digest) {
  Lookup result = checked(digest, /*with_bytes=*/true);
  if (result.found == Found::kSetAside) throw ServiceError(Kind::kDataLoss, corrupted_mesh_message(digest));
  if (result.found == Found::kAbsent) return std::nullopt;
  return std::move(result.info);
}

std::optional<MeshInfo> PgMeshStore::find_intact(const std::string& digest) {
  Lookup result = checked(digest, /*with_bytes=*/true);
  if (result.found != Found::kIntact) return std::nullopt;
  return std::move(result.info);
}

std::vector<MeshInfo> PgMeshStore::list() {
  const pqxx::result rows = database_.transaction([](pqxx::work& txn) {
    return txn.exec("SELECT digest, description, octet_length(bytes) AS size FROM isocorr_meshes "
                    "WHERE set_aside IS NULL ORDER BY digest");
  });
  std::vector<MeshInfo> meshes;
  for (const auto& row : rows) {
    const std::string digest = row["digest"].as<std::string>();
    MeshInfo info;
    std::string no_bytes;
    if (problem_of(digest, row, /*with_bytes=*/false, info, no_bytes).empty()) {
      meshes.push_back(std::move(info));
      continue;
    }
    Lookup again = checked(digest, /*with_bytes=*/false);  // sets it aside unless repaired meanwhile
    if (again.found == Found::kIntact) meshes.push_back(std::move(again.info));
  }
  return meshes;
}

bool PgMeshStore::remove(const std::string& digest) {
  return database_.transaction([&](pqxx::work& txn) {
    return !txn.exec_params("DELETE FROM isocorr_meshes WHERE digest = $1 RETURNING digest", digest).empty();
  });
}

PgMeshStore::StoredMesh PgMeshStore::read(const std::string& digest) {
  Lookup result = checked(digest, /*with_bytes=*/true);
  if (result.found == Found::kSetAside) throw ServiceError(Kind::kDataLoss, corrupted_mesh_message(digest));
  if (result.found == Found::kAbsent)
    throw ServiceError(Kind::kNotFound, "no mesh meshes/" + digest + " on this server; upload it first");
  return {std::move(result.info), std::move(result.bytes)};
}

}  // namespace isocorr::server
