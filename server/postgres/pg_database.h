// A PostgreSQL database that several isocorr-server replicas share (--store
// postgresql://...): a small pool of connections, the schema created at start, and
// database errors turned into the service's own (ServiceError).
//
// Schema version 1 (created idempotently under an advisory lock, so replicas starting
// together do not race; a database with a newer version is refused):
//   isocorr_schema(version)                        one row
//   isocorr_meshes(digest PK, description, bytes, set_aside)
//       description: the sealed JSON of MeshInfo; bytes: the file; set_aside: why the mesh
//       was found corrupted (NULL while intact)
//   isocorr_jobs(id PK, record, state, source_digest, target_digest, create_time_ms,
//                version, progress, created_by, claimed_by, lease_until, cancel_requested)
//       record: the sealed JSON the journal would write; state and the digests repeat it
//       for queries; the queue is the QUEUED rows, and RUNNING rows whose lease expired;
//       created_by: the replica that received CreateMatchJob (it claims those first)
//   isocorr_results(job_id PK, manifest, set_aside)
//   isocorr_result_parts(job_id, part, bytes)      PK (job_id, part)
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <pqxx/pqxx>

namespace isocorr::server {

inline constexpr int kPgSchemaVersion = 2;

class PgDatabase {
 public:
  // Connects and creates the schema. Throws std::runtime_error when the database cannot
  // be reached or holds a newer schema.
  explicit PgDatabase(std::string url);

  // Runs `work` in one transaction and commits it. Database failures become ServiceError
  // kUnavailable when the database cannot be reached, kResourceExhausted when it is out of
  // disk or memory, std::runtime_error (INTERNAL) otherwise; the log has the details. A
  // broken connection is dropped from the pool.
  template <typename Work>
  auto transaction(Work&& work) {
    using Result = decltype(work(std::declval<pqxx::work&>()));
    if constexpr (std::is_void_v<Result>) {
      run([&](pqxx::work& txn) { work(txn); });
    } else {
      Result result{};
      run([&](pqxx::work& txn) { result = work(txn); });
      return result;
    }
  }

 private:
  void run(const std::function<void(pqxx::work&)>& work);
  std::unique_ptr<pqxx::connection> borrow();
  void give_back(std::unique_ptr<pqxx::connection> connection);
  void create_schema();

  const std::string url_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<pqxx::connection>> idle_;
};

}  // namespace isocorr::server
