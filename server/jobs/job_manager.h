// The job queue and its fixed pool of worker threads. Owns every job's state; the journal
// makes each acknowledged change durable before it is visible to callers.
//
// Restart semantics: jobs found QUEUED or RUNNING in the journal are queued again (a
// RUNNING one was interrupted by a crash or kill) until a job has been started
// `max_attempts` times, then it is marked FAILED with the reason: by default a job that
// stopped the server twice is not run a third time. A graceful shutdown puts running jobs
// back to QUEUED without counting the attempt. A finished job is never run again: its
// end is shown only once it is on disk.
//
// Full disk: a queued job whose start cannot be recorded stays QUEUED (stage "waiting for
// disk space") and is tried again every few seconds; a job whose result cannot be written
// ends FAILED with RESOURCE_EXHAUSTED and the reason; a job whose end cannot be recorded
// stays RUNNING (stage "waiting for disk space to record its end") until it can be (after
// a restart meanwhile it runs again, as nobody saw it end). A corrupted stored mesh fails
// its job with DATA_LOSS. No job stays RUNNING or QUEUED for want of disk space once it returns.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "jobs/job_coordinator.h"
#include "jobs/shape_cache.h"
#include "storage/job_record.h"
#include "storage/job_journal.h"
#include "storage/mesh_store.h"

namespace isocorr::server {

struct JobManagerOptions {
  int workers = 1;            // jobs running at once
  int max_queued_jobs = 64;   // CreateMatchJob beyond this is RESOURCE_EXHAUSTED
  int max_attempts = 2;       // starts before an interrupted job is given up
  std::chrono::seconds time_limit{0};  // a run past it fails with DEADLINE_EXCEEDED; 0 = none
};

class JobManager final : public JobCoordinator {
 public:
  JobManager(JobManagerOptions options, MeshRepository& meshes, JobJournal& journal, ShapeCache& cache);
  ~JobManager() override;

  // Reads the journal, re-queues unfinished jobs and starts the workers.
  void recover_and_start() override;
  // Stops the workers; running jobs go back to QUEUED in the journal.
  void shutdown() override;

  JobRecord create(const std::string& source_digest, const std::string& target_digest,
                   const MatchSettings& settings, const std::string& request_id) override;
  JobRecord get(const std::string& id) const override;
  std::vector<JobRecord> list() const override;
  JobRecord cancel(const std::string& id) override;
  JobRecord wait_for_change(const std::string& id, uint64_t seen_version,
                            std::chrono::steady_clock::time_point deadline) const override;
  bool mesh_in_use(const std::string& digest) const override;
  const ResultReader& results() const override { return journal_; }
  Census census() const override;

 private:
  struct Slot {
    JobRecord record;
    std::atomic<bool> cancel_requested{false};
  };
  void worker_loop();
  void run(Slot& slot);
  void finish(Slot& slot, JobRecord final_record);
  Slot& slot_locked(const std::string& id) const;
  void publish_locked(Slot& slot);

  const JobManagerOptions options_;
  MeshRepository& meshes_;
  JobJournal& journal_;
  ShapeCache& cache_;

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;  // some job changed (wakes waiters and watchers)
  std::condition_variable work_available_;
  std::deque<std::string> queue_;
  std::map<std::string, std::unique_ptr<Slot>> jobs_;
  std::vector<std::thread> workers_;
  bool stopping_ = false;
};

}  // namespace isocorr::server
