// What the API asks of the jobs, whoever keeps them: one server with its journal in the
// data directory (JobManager) or several replicas sharing a database (SharedJobManager).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "isocorr/output/match_result.h"
#include "isocorr/settings/match_settings.h"
#include "service_error.h"
#include "storage/job_record.h"
#include "storage/mesh_repository.h"
#include "storage/result_parts.h"

namespace isocorr::server {

class JobCoordinator {
 public:
  virtual ~JobCoordinator() = default;

  // Re-queues unfinished jobs as the store requires and starts the workers.
  virtual void recover_and_start() = 0;
  // Stops the workers; running jobs go back to QUEUED.
  virtual void shutdown() = 0;

  // Durable when it returns. Throws ServiceError (kNotFound, kInvalidArgument,
  // kResourceExhausted, kUnavailable while shutting down).
  // `request_id` is the creating call's, kept in the record and named by the job's log lines.
  virtual JobRecord create(const std::string& source_digest, const std::string& target_digest,
                           const MatchSettings& settings, const std::string& request_id) = 0;
  virtual JobRecord get(const std::string& id) const = 0;  // throws ServiceError(kNotFound)
  virtual std::vector<JobRecord> list() const = 0;         // oldest first
  // A queued job ends CANCELLED at once, a running one at the engine's next safe point.
  virtual JobRecord cancel(const std::string& id) = 0;
  // Returns as soon as the job's version differs from `seen_version` or it is final, or at
  // `deadline` with the job as it is.
  virtual JobRecord wait_for_change(const std::string& id, uint64_t seen_version,
                                    std::chrono::steady_clock::time_point deadline) const = 0;
  virtual bool mesh_in_use(const std::string& digest) const = 0;
  virtual const ResultReader& results() const = 0;

  // For the metrics endpoint: the jobs this server answers for (all replicas' on a shared
  // store), by state, and how many wait for a worker.
  struct Census {
    std::map<JobState, int> by_state;
    size_t queue_length = 0;  // QUEUED jobs (on a shared store: in the queue of all replicas)
  };
  virtual Census census() const = 0;

 protected:
  // What create checks first, wherever jobs are kept: the settings (kInvalidArgument) and
  // that both meshes are stored (kNotFound, or kDataLoss for a corrupted one).
  static void check_new_job(MeshRepository& meshes, const std::string& source_digest,
                            const std::string& target_digest, const MatchSettings& settings);
  // A new QUEUED job with a fresh id, created now.
  static JobRecord new_job(const std::string& source_digest, const std::string& target_digest,
                           const MatchSettings& settings, const std::string& request_id);
  // The kResourceExhausted refusal when `queued` jobs reach --max-queued-jobs.
  static ServiceError queue_full(size_t queued);
};

}  // namespace isocorr::server
