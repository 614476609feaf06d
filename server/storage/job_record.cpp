#include "storage/job_record.h"

#include <chrono>
#include <mutex>
#include <random>

namespace isocorr::server {

const char* job_state_name(JobState state) {
  switch (state) {
    case JobState::kQueued: return "QUEUED";
    case JobState::kRunning: return "RUNNING";
    case JobState::kSucceeded: return "SUCCEEDED";
    case JobState::kFailed: return "FAILED";
    case JobState::kCancelled: return "CANCELLED";
  }
  return "UNKNOWN";
}

bool is_final(JobState state) {
  return state == JobState::kSucceeded || state == JobState::kFailed || state == JobState::kCancelled;
}

std::string job_tag(const JobRecord& job) {
  std::string tag = "job " + job.id;
  if (!job.created_by_request.empty()) tag.append(" from ").append(job.created_by_request);
  return tag;
}

int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string new_job_id() {
  static std::mutex mutex;
  static std::mt19937_64 generator{std::random_device{}()};
  std::lock_guard lock(mutex);
  static const char* hex = "0123456789abcdef";
  std::string id;
  for (uint64_t bits = generator(), i = 0; i < 16; ++i, bits >>= 4) id += hex[bits & 15];
  return id;
}

}  // namespace isocorr::server
