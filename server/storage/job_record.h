// A matching job as the server keeps it: plain data, no protobuf, so the queue, the
// journal and the workers do not depend on the API's generated code.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "isocorr/output/match_result.h"
#include "isocorr/settings/match_settings.h"

namespace isocorr::server {

enum class JobState { kQueued, kRunning, kSucceeded, kFailed, kCancelled };

const char* job_state_name(JobState state);
bool is_final(JobState state);

// google.rpc.Code values used for job errors (stable numbers, shared with gRPC).
enum class ErrorCode : int {
  kCancelled = 1, kInvalidArgument = 3, kDeadlineExceeded = 4, kNotFound = 5, kResourceExhausted = 8, kAborted = 10, kInternal = 13,
  kDataLoss = 15
};

struct JobProgressInfo {
  std::string stage = "queued";
  int level = 0, levels = 0;
  double fraction = 0;
};

struct JobRecord {
  std::string id;  // the name is "jobs/" + id
  JobState state = JobState::kQueued;
  std::string source_digest, target_digest;
  MatchSettings settings;
  JobProgressInfo progress;  // in memory only
  int64_t create_time_ms = 0, start_time_ms = 0, end_time_ms = 0;
  int attempts = 0;
  MatchSummary summary;      // when kSucceeded
  ErrorCode error_code = ErrorCode::kInternal;  // when kFailed or kCancelled
  std::string error_message;
  uint64_t version = 0;      // bumped on every change; watchers wait for a new one
  std::string created_by_request;  // the CreateMatchJob call's request id ("" in older records)
};

// "job {id} from {request}" (or "job {id}"), the prefix of every log line about the job.
std::string job_tag(const JobRecord& job);

int64_t now_ms();
// 16 random hex digits: a job's id, unique across replicas in practice (64 bits).
std::string new_job_id();

}  // namespace isocorr::server
