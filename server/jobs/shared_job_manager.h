// Jobs of several replicas sharing one PostgreSQL store (--store postgresql://...). The
// database holds every job's state (PgJobStore); each replica runs a few workers that
// claim queued jobs there, and one lease keeper that renews the leases of the jobs it
// runs, records their progress and picks up cancel requests made through any replica.
// A replica that dies loses nothing: its jobs' leases expire and other replicas take them.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "jobs/job_coordinator.h"
#include "jobs/shape_cache.h"
#include "postgres/pg_job_store.h"
#include "storage/mesh_repository.h"

namespace isocorr::server {

struct SharedJobOptions {
  int workers = 1;
  int max_queued_jobs = 64;             // across all replicas
  int max_attempts = 2;
  std::chrono::milliseconds lease{30000};
  std::string replica;                  // claimed_by of this replica's jobs; unique per process
  std::chrono::seconds time_limit{0};   // a run past it fails with DEADLINE_EXCEEDED; 0 = none
};

class SharedJobManager final : public JobCoordinator {
 public:
  SharedJobManager(SharedJobOptions options, PgJobStore& store, MeshRepository& meshes, ShapeCache& cache);
  ~SharedJobManager() override;

  void recover_and_start() override;
  void shutdown() override;
  JobRecord create(const std::string& source_digest, const std::string& target_digest,
                   const MatchSettings& settings, const std::string& request_id) override;
  JobRecord get(const std::string& id) const override;
  std::vector<JobRecord> list() const override { return store_.list(); }
  JobRecord cancel(const std::string& id) override;
  JobRecord wait_for_change(const std::string& id, uint64_t seen_version,
                            std::chrono::steady_clock::time_point deadline) const override;
  bool mesh_in_use(const std::string& digest) const override { return store_.mesh_in_use(digest); }
  const ResultReader& results() const override { return store_; }
  // Every replica's jobs, from the shared store: each replica reports the same numbers.
  Census census() const override;

 private:
  struct Running {
    std::atomic<bool> cancel_requested{false};
    std::atomic<bool> lease_lost{false};
    JobProgressInfo progress;  // guarded by mutex_
  };
  void worker_loop();
  void run(const JobRecord& job);
  // Records the job's end; a result that does not fit ends it FAILED (RESOURCE_EXHAUSTED).
  void finish(JobRecord final_record, const EncodedResult* result);
  void keep_leases();
  // Sleeps until `interval` passed, a job was created here or the manager stops; false
  // when stopping.
  bool pause(std::chrono::milliseconds interval);

  const SharedJobOptions options_;
  PgJobStore& store_;
  MeshRepository& meshes_;
  ShapeCache& cache_;

  mutable std::mutex mutex_;
  mutable std::condition_variable wake_;  // stopping, or a job was created here
  uint64_t jobs_created_ = 0;
  std::map<std::string, std::shared_ptr<Running>> running_;
  std::vector<std::thread> threads_;
  bool stopping_ = false;
};

}  // namespace isocorr::server
