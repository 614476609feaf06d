#include "jobs/shared_job_manager.h"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "isocorr/util/error.h"
#include "jobs/job_execution.h"
#include "metrics/server_metrics.h"
#include "service_error.h"

namespace isocorr::server {
using Kind = ServiceError::Kind;
using std::chrono::milliseconds;

namespace {

// How often an idle worker looks for jobs queued through other replicas.
constexpr milliseconds kClaimPollInterval{500};
// How often a waiting call looks at its job again (other replicas change it).
constexpr milliseconds kWaitPollInterval{200};

// A lease is renewed three times per lease period, and at least once a second so that
// progress shows through every replica.
milliseconds renewal_interval(milliseconds lease) {
  return std::clamp(lease / 3, milliseconds{50}, milliseconds{1000});
}

}  // namespace

SharedJobManager::SharedJobManager(SharedJobOptions options, PgJobStore& store, MeshRepository& meshes,
                                   ShapeCache& cache)
    : options_(std::move(options)), store_(store), meshes_(meshes), cache_(cache) {}

SharedJobManager::~SharedJobManager() { shutdown(); }

void SharedJobManager::recover_and_start() {
  // Nothing to recover here: jobs of a replica that died are claimed again once their
  // leases expire, by whichever replica comes first.
  for (int i = 0; i < std::max(1, options_.workers); ++i) threads_.emplace_back([this] { worker_loop(); });
  threads_.emplace_back([this] { keep_leases(); });
  spdlog::info("jobs: replica {} on the shared store, lease {} ms", options_.replica, options_.lease.count());
}

void SharedJobManager::shutdown() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && threads_.empty()) return;
    stopping_ = true;
    for (auto& [id, running] : running_) running->cancel_requested = true;
  }
  wake_.notify_all();
  for (auto& thread : threads_) thread.join();
  threads_.clear();
}

JobRecord SharedJobManager::create(const std::string& source_digest, const std::string& target_digest,
                                   const MatchSettings& settings, const std::string& request_id) {
  check_new_job(meshes_, source_digest, target_digest, settings);
  {
    std::lock_guard lock(mutex_);
    if (stopping_) throw ServiceError(Kind::kUnavailable, "the server is shutting down; retry on another replica");
  }
  const int queued = store_.count_queued();
  if (queued >= options_.max_queued_jobs) throw queue_full(queued);
  JobRecord record = new_job(source_digest, target_digest, settings, request_id);
  store_.insert(record, options_.replica);
  record.version = 1;
  {
    std::lock_guard lock(mutex_);
    ++jobs_created_;
  }
  wake_.notify_all();
  spdlog::info("[{}] queued in the shared store: {} -> {}", job_tag(record), source_digest.substr(0, 12),
               target_digest.substr(0, 12));
  return record;
}

JobCoordinator::Census SharedJobManager::census() const {
  Census census;
  census.by_state = store_.count_by_state();
  census.queue_length = census.by_state[JobState::kQueued];
  return census;
}

JobRecord SharedJobManager::get(const std::string& id) const {
  std::optional<JobRecord> job = store_.find(id);
  if (!job) throw ServiceError(Kind::kNotFound, "no job jobs/" + id + " on this server");
  return std::move(*job);
}

JobRecord SharedJobManager::cancel(const std::string& id) {
  JobRecord job = store_.cancel(id);
  {
    std::lock_guard lock(mutex_);
    if (auto it = running_.find(id); it != running_.end()) it->second->cancel_requested = true;
  }
  spdlog::info("[{}] cancel requested", job_tag(job));
  return job;
}

JobRecord SharedJobManager::wait_for_change(const std::string& id, uint64_t seen_version,
                                            std::chrono::steady_clock::time_point deadline) const {
  for (;;) {
    JobRecord job = get(id);
    if (job.version != seen_version || is_final(job.state) || std::chrono::steady_clock::now() >= deadline) return job;
    std::unique_lock lock(mutex_);
    const auto next = std::min(deadline, std::chrono::steady_clock::now() + kWaitPollInterval);
    if (wake_.wait_until(lock, next, [&] { return stopping_; })) return job;
  }
}

void SharedJobManager::worker_loop() {
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (stopping_) return;
    }
    std::optional<JobRecord> job;
    try {
      job = store_.claim(options_.replica, options_.lease, options_.max_attempts);
    } catch (const std::exception& e) {  // the database is unreachable: tried again shortly
      spdlog::error("jobs: cannot claim a job from the shared store: {}", e.what());
    }
    if (job) {
      run(*job);
    } else if (!pause(kClaimPollInterval)) {
      return;
    }
  }
}

bool SharedJobManager::pause(milliseconds interval) {
  std::unique_lock lock(mutex_);
  const uint64_t seen = jobs_created_;
  wake_.wait_for(lock, interval, [&] { return stopping_ || jobs_created_ != seen; });
  return !stopping_;
}

void SharedJobManager::run(const JobRecord& job) {
  auto running = std::make_shared<Running>();
  {
    std::lock_guard lock(mutex_);
    running->progress = job.progress;
    if (stopping_) running->cancel_requested = true;
    running_[job.id] = running;
  }
  spdlog::info("[{}] running on replica {} (attempt {})", job_tag(job), options_.replica, job.attempts);
  JobControl control;
  control.cancel_requested = &running->cancel_requested;
  control.deadline = run_deadline(options_.time_limit);
  control.on_progress = [&](const Progress& p) {
    std::lock_guard lock(mutex_);
    running->progress = {p.stage, p.level, p.levels, p.fraction};
  };

  std::optional<EncodedResult> result;
  std::optional<JobRecord> final_record;
  try {
    final_record = run_to_conclusion(job, meshes_, cache_, control,
                                     [&](const MatchOutput& output) { result = encode_result(job, output); });
  } catch (const Cancelled&) {
    bool stopping = false;
    {
      std::lock_guard lock(mutex_);
      stopping = stopping_;
    }
    if (running->lease_lost) {
      spdlog::warn("[{}] lease lost to another replica; stopped here", job_tag(job));
    } else if (stopping) {
      try {
        store_.requeue(job, options_.replica);  // another replica takes it at once
        spdlog::info("[{}] interrupted by shutdown; queued again", job_tag(job));
      } catch (const std::exception& e) {  // its lease expires and another replica takes it
        spdlog::error("[{}] cannot queue it again: {}", job_tag(job), e.what());
      }
    } else {
      final_record = job;
      final_record->state = JobState::kCancelled;
      final_record->error_code = ErrorCode::kCancelled;
      final_record->error_message = "cancelled while running";
      spdlog::info("[{}] cancelled", job_tag(job));
    }
  }
  if (final_record) finish(*final_record, result ? &*result : nullptr);
  std::lock_guard lock(mutex_);
  running_.erase(job.id);
}

void SharedJobManager::finish(JobRecord final_record, const EncodedResult* result) {
  final_record.end_time_ms = now_ms();
  try {
    try {
      if (store_.finish(final_record, options_.replica, result))
        record_job_durations(final_record);
      else  // the replica that holds it now records its end
        spdlog::warn("[{}] lease lost to another replica before the end was recorded", job_tag(final_record));
      return;
    } catch (const ServiceError& e) {
      if (final_record.state != JobState::kSucceeded || e.kind() != ServiceError::Kind::kResourceExhausted) throw;
      // The result does not fit in the store: the job ends FAILED with the reason.
      final_record.state = JobState::kFailed;
      final_record.error_code = ErrorCode::kResourceExhausted;
      final_record.error_message = std::string("cannot store the result: ") + e.what();
    }
    if (store_.finish(final_record, options_.replica, nullptr)) record_job_durations(final_record);
  } catch (const std::exception& e) {
    // Not recorded: the job stays RUNNING under a lease nobody renews, so it runs again
    // (here or on another replica) once the lease has expired.
    spdlog::error("[{}] cannot record its end: {}", job_tag(final_record), e.what());
  }
}

void SharedJobManager::keep_leases() {
  const milliseconds interval = renewal_interval(options_.lease);
  for (;;) {
    std::vector<std::pair<std::string, std::shared_ptr<Running>>> jobs;
    std::vector<JobProgressInfo> progress;
    {
      std::unique_lock lock(mutex_);
      if (stopping_ && running_.empty()) return;
      for (const auto& [id, running] : running_) {
        jobs.emplace_back(id, running);
        progress.push_back(running->progress);
      }
    }
    for (size_t i = 0; i < jobs.size(); ++i) {
      const auto& [id, running] = jobs[i];
      try {
        const PgJobStore::Renewal renewal = store_.renew(id, options_.replica, options_.lease, progress[i]);
        if (!renewal.held) {
          running->lease_lost = true;
          running->cancel_requested = true;
        } else if (renewal.cancel_requested) {
          running->cancel_requested = true;
        }
      } catch (const std::exception& e) {  // tried again at the next renewal
        spdlog::error("[job {}] cannot renew its lease: {}", id, e.what());
      }
    }
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, interval);
  }
}

}  // namespace isocorr::server
