// Job records, the job queue and results in the shared PostgreSQL database, so that any
// replica answers for any job and a job outlives the replica that ran it.
//
// Claims and leases: a worker claims a claimable job with
//   SELECT ... FROM isocorr_jobs WHERE state = 'QUEUED' OR (state = 'RUNNING' AND
//   lease_until < now()) ORDER BY created_by IS DISTINCT FROM <replica>, create_time_ms, id
//   LIMIT 1 FOR UPDATE SKIP LOCKED
// (so two replicas never take the same row and neither waits for the other's lock; the
// jobs created through this replica first, whose meshes its cache is likely to hold), and
// marks it RUNNING with claimed_by = its replica id and lease_until = now() + the lease.
// The running replica renews the lease (and records progress) well before it expires; a
// replica that dies stops renewing, and once the lease has expired the job is claimable
// again: another replica runs it (a new attempt; after --max-attempts it FAILS instead).
// Every later write of a running job (renewal, the end, a requeue) requires claimed_by to
// still be the writer, so a replica that lost its lease cannot overwrite the new runner.
// Cancel sets cancel_requested on a running job's row; the runner sees it at its next renewal.
#pragma once

#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "postgres/pg_database.h"
#include "storage/job_record.h"
#include "storage/result_parts.h"

namespace isocorr::server {

class PgJobStore final : public ResultReader {
 public:
  explicit PgJobStore(PgDatabase& database) : database_(database) {}

  void insert(const JobRecord& job, const std::string& replica);
  std::optional<JobRecord> find(const std::string& id) const;
  std::vector<JobRecord> list() const;  // oldest first
  int count_queued() const;
  std::map<JobState, int> count_by_state() const;  // all replicas' jobs
  bool mesh_in_use(const std::string& digest) const;
  // Throws ServiceError(kNotFound, kFailedPrecondition when already final).
  JobRecord cancel(const std::string& id);

  // The oldest claimable job created through `replica`, else the oldest of all, now RUNNING for `replica` until now() + lease; nullopt when
  // none. Jobs whose lease expired `max_attempts` times end FAILED (ABORTED) instead, and
  // an expired job whose cancel was requested ends CANCELLED.
  std::optional<JobRecord> claim(const std::string& replica, std::chrono::milliseconds lease, int max_attempts);
  struct Renewal {
    bool held = false;              // false: the lease was lost to another replica
    bool cancel_requested = false;
  };
  // Extends the lease and records progress (a changed progress bumps the version).
  Renewal renew(const std::string& id, const std::string& replica, std::chrono::milliseconds lease,
                const JobProgressInfo& progress);
  // Records the job's end (and its result, in the same transaction) if `replica` still
  // holds it; false otherwise (nothing written).
  bool finish(const JobRecord& final_record, const std::string& replica, const EncodedResult* result);
  // Puts a running job back in the queue without counting the attempt (graceful stop).
  void requeue(const JobRecord& running, const std::string& replica);

  // The schema upgrade to manifests that name their job: binds each result written before
  // to the record of its job (once, under the schema lock).
  static void bind_results_to_their_jobs(pqxx::work& txn);

 protected:
  std::string read_checked_part(const JobRecord& job, ResultPart part) const override;

 private:
  // Writes record, state and version+1 of a row already locked.
  static void write_record(pqxx::work& txn, const JobRecord& job);
  [[noreturn]] void result_lost(const std::string& id, const std::string& problem) const;

  PgDatabase& database_;
};

}  // namespace isocorr::server
