#include "jobs/job_manager.h"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "isocorr/util/error.h"
#include "jobs/job_execution.h"
#include "metrics/server_metrics.h"
#include "service_error.h"

namespace isocorr::server {
using Kind = ServiceError::Kind;

namespace {

// A queued job whose start cannot be recorded (full disk) is tried again this often, and
// shows this stage meanwhile.
constexpr auto kDiskRetryInterval = std::chrono::seconds(2);
constexpr const char* kWaitingForDisk = "waiting for disk space";
// A job whose end cannot be recorded shows this stage and stays RUNNING until it is.
constexpr const char* kWaitingToRecordEnd = "waiting for disk space to record its end";

std::string times(int count) {
  return count == 1 ? "once" : count == 2 ? "twice" : std::to_string(count) + " times";
}

// A job's meshes as recovery finds them: fails `record` when one is gone or corrupted.
bool fail_if_mesh_missing(MeshRepository& meshes, JobRecord& record) {
  try {
    if (meshes.describe(record.source_digest) && meshes.describe(record.target_digest)) return false;
    record.error_code = ErrorCode::kNotFound;
    record.error_message = "a mesh of this job is no longer on the server";
  } catch (const ServiceError& e) {
    record.error_code = error_code_for(e.kind());
    record.error_message = e.what();
  }
  record.state = JobState::kFailed;
  record.end_time_ms = now_ms();
  return true;
}

}  // namespace

JobManager::JobManager(JobManagerOptions options, MeshRepository& meshes, JobJournal& journal, ShapeCache& cache)
    : options_(options), meshes_(meshes), journal_(journal), cache_(cache) {}

JobManager::~JobManager() { shutdown(); }

void JobManager::recover_and_start() {
  std::vector<JobRecord> records = journal_.load_all();
  std::sort(records.begin(), records.end(),
            [](const JobRecord& a, const JobRecord& b) { return a.create_time_ms < b.create_time_ms; });
  std::lock_guard lock(mutex_);
  for (JobRecord& record : records) {
    if (!is_final(record.state)) {
      const bool was_running = record.state == JobState::kRunning;
      if (was_running && record.attempts >= options_.max_attempts) {
        record.state = JobState::kFailed;
        record.error_code = ErrorCode::kAborted;
        record.error_message = "this job stopped the server " + times(record.attempts) +
                               " while running (crash, kill or out of memory); not run again";
        record.end_time_ms = now_ms();
      } else if (!fail_if_mesh_missing(meshes_, record)) {
        record.state = JobState::kQueued;
        record.progress = {};
        queue_.push_back(record.id);
      }
      try {
        journal_.save(record);
      } catch (const std::exception& e) {  // full disk: the journal keeps the old state, re-read next start
        spdlog::error("[{}] cannot write its journal record: {}", job_tag(record), e.what());
      }
      spdlog::info("[{}] recovered: {}{}", job_tag(record), job_state_name(record.state),
                   was_running ? " (was running when the server stopped)" : "");
    }
    auto slot = std::make_unique<Slot>();
    slot->record = std::move(record);
    jobs_.emplace(slot->record.id, std::move(slot));
  }
  for (int i = 0; i < std::max(1, options_.workers); ++i) workers_.emplace_back([this] { worker_loop(); });
}

void JobManager::shutdown() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && workers_.empty()) return;
    stopping_ = true;
    for (auto& [id, slot] : jobs_)
      if (slot->record.state == JobState::kRunning) slot->cancel_requested = true;
  }
  work_available_.notify_all();
  changed_.notify_all();
  for (auto& worker : workers_) worker.join();
  workers_.clear();
}

JobRecord JobManager::create(const std::string& source_digest, const std::string& target_digest,
                             const MatchSettings& settings, const std::string& request_id) {
  check_new_job(meshes_, source_digest, target_digest, settings);

  std::lock_guard lock(mutex_);
  if (stopping_) throw ServiceError(Kind::kUnavailable, "the server is shutting down; retry on its next start");
  if (static_cast<int>(queue_.size()) >= options_.max_queued_jobs) throw queue_full(queue_.size());
  auto slot = std::make_unique<Slot>();
  slot->record = new_job(source_digest, target_digest, settings, request_id);
  JobRecord& record = slot->record;
  journal_.save(record);
  queue_.push_back(record.id);
  const JobRecord created = record;
  jobs_.emplace(record.id, std::move(slot));
  work_available_.notify_one();
  spdlog::info("[{}] queued: {} -> {} ({} in queue)", job_tag(created), source_digest.substr(0, 12),
               target_digest.substr(0, 12), queue_.size());
  return created;
}

JobManager::Slot& JobManager::slot_locked(const std::string& id) const {
  auto it = jobs_.find(id);
  if (it == jobs_.end()) throw ServiceError(Kind::kNotFound, "no job jobs/" + id + " on this server");
  return *it->second;
}

void JobManager::publish_locked(Slot& slot) {
  ++slot.record.version;
  changed_.notify_all();
}

JobRecord JobManager::get(const std::string& id) const {
  std::lock_guard lock(mutex_);
  return slot_locked(id).record;
}

std::vector<JobRecord> JobManager::list() const {
  std::lock_guard lock(mutex_);
  std::vector<JobRecord> records;
  for (const auto& [id, slot] : jobs_) records.push_back(slot->record);
  std::sort(records.begin(), records.end(), [](const JobRecord& a, const JobRecord& b) {
    return std::tie(a.create_time_ms, a.id) < std::tie(b.create_time_ms, b.id);
  });
  return records;
}

JobRecord JobManager::cancel(const std::string& id) {
  std::lock_guard lock(mutex_);
  Slot& slot = slot_locked(id);
  JobRecord& record = slot.record;
  if (is_final(record.state))
    throw ServiceError(Kind::kFailedPrecondition,
                       "job jobs/" + id + " is already " + job_state_name(record.state) + "; nothing to cancel");
  if (record.state == JobState::kQueued) {
    JobRecord cancelled = record;
    cancelled.state = JobState::kCancelled;
    cancelled.error_code = ErrorCode::kCancelled;
    cancelled.error_message = "cancelled before it started";
    cancelled.end_time_ms = now_ms();
    journal_.save(cancelled);  // throws on a full disk, leaving the job queued as it was
    queue_.erase(std::remove(queue_.begin(), queue_.end(), id), queue_.end());
    record = cancelled;
    publish_locked(slot);
  }
  slot.cancel_requested = true;
  spdlog::info("[{}] cancel requested", job_tag(record));
  return record;
}

JobRecord JobManager::wait_for_change(const std::string& id, uint64_t seen_version,
                                      std::chrono::steady_clock::time_point deadline) const {
  std::unique_lock lock(mutex_);
  Slot& slot = slot_locked(id);
  changed_.wait_until(lock, deadline, [&] {
    return slot.record.version != seen_version || is_final(slot.record.state);
  });
  return slot.record;
}

JobManager::Census JobManager::census() const {
  std::lock_guard lock(mutex_);
  Census census;
  for (const auto& [id, slot] : jobs_) ++census.by_state[slot->record.state];
  census.queue_length = queue_.size();
  return census;
}

bool JobManager::mesh_in_use(const std::string& digest) const {
  std::lock_guard lock(mutex_);
  for (const auto& [id, slot] : jobs_)
    if (!is_final(slot->record.state) &&
        (slot->record.source_digest == digest || slot->record.target_digest == digest))
      return true;
  return false;
}

void JobManager::worker_loop() {
  for (;;) {
    Slot* slot = nullptr;
    {
      std::unique_lock lock(mutex_);
      work_available_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      slot = jobs_.at(queue_.front()).get();
      JobRecord running = slot->record;
      running.state = JobState::kRunning;
      running.attempts += 1;
      running.start_time_ms = now_ms();
      running.progress = {"starting", 0, 0, 0};
      try {
        journal_.save(running);  // a crash from here on counts as an attempt
      } catch (const std::exception& e) {
        // Cannot record the start (full disk): the job stays first in the queue, shows why,
        // and is tried again shortly, so it runs once space returns.
        if (slot->record.progress.stage != kWaitingForDisk) {
          spdlog::error("[{}] cannot record its start, retrying every {} s: {}", job_tag(running),
                        kDiskRetryInterval.count(), e.what());
          slot->record.progress.stage = kWaitingForDisk;
          publish_locked(*slot);
        }
        work_available_.wait_for(lock, kDiskRetryInterval, [&] { return stopping_; });
        continue;
      }
      queue_.pop_front();
      slot->record = running;
      publish_locked(*slot);
    }
    run(*slot);
  }
}

void JobManager::run(Slot& slot) {
  JobRecord job;
  {
    std::lock_guard lock(mutex_);
    job = slot.record;
  }
  spdlog::info("[{}] running (attempt {})", job_tag(job), job.attempts);
  JobControl control;
  control.cancel_requested = &slot.cancel_requested;
  control.deadline = run_deadline(options_.time_limit);
  control.on_progress = [&](const Progress& p) {
    std::lock_guard lock(mutex_);
    slot.record.progress = {p.stage, p.level, p.levels, p.fraction};
    publish_locked(slot);
    spdlog::debug("[{}] {} level {}/{} {:.0f}%", job_tag(job), p.stage, p.level, p.levels, 100 * p.fraction);
  };

  JobRecord final_record;
  try {
    final_record = run_to_conclusion(job, meshes_, cache_, control,
                                     [&](const MatchOutput& output) { journal_.save_result(job, output); });
  } catch (const Cancelled&) {
    std::unique_lock lock(mutex_);
    if (stopping_) {
      // Graceful shutdown: the job runs again at the next start, and this start does not count.
      JobRecord requeued = slot.record;
      requeued.state = JobState::kQueued;
      requeued.attempts -= 1;
      requeued.progress = {};
      try {
        journal_.save(requeued);
      } catch (const std::exception& e) {  // the journal says RUNNING: the next start counts it
        spdlog::error("[{}] cannot write its journal record: {}", job_tag(job), e.what());
      }
      slot.record = requeued;
      publish_locked(slot);
      spdlog::info("[{}] interrupted by shutdown; queued again for the next start", job_tag(job));
      return;
    }
    lock.unlock();
    final_record = job;
    final_record.state = JobState::kCancelled;
    final_record.error_code = ErrorCode::kCancelled;
    final_record.error_message = "cancelled while running";
    spdlog::info("[{}] cancelled", job_tag(job));
  }
  finish(slot, std::move(final_record));
}

void JobManager::finish(Slot& slot, JobRecord final_record) {
  std::unique_lock lock(mutex_);
  final_record.end_time_ms = now_ms();  // whatever the outcome: the time the job ended
  // A job is seen done only once its end is on disk: a state a caller saw final must be
  // the state the next start reads. Until then (full disk) it stays RUNNING, saying why.
  for (;;) {
    try {
      journal_.save(final_record);
      break;
    } catch (const std::exception& e) {
      if (slot.record.progress.stage != kWaitingToRecordEnd) {
        spdlog::error("[{}] cannot record its end ({}), retrying every {} s: {}", job_tag(final_record),
                      job_state_name(final_record.state), kDiskRetryInterval.count(), e.what());
        slot.record.progress.stage = kWaitingToRecordEnd;
        publish_locked(slot);
      }
    }
    // Stopping: the journal still says RUNNING, so the job runs again at the next start.
    if (changed_.wait_for(lock, kDiskRetryInterval, [&] { return stopping_; })) return;
  }
  final_record.version = slot.record.version;
  record_job_durations(final_record);
  slot.record = std::move(final_record);
  publish_locked(slot);
}

}  // namespace isocorr::server
