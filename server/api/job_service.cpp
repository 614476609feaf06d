#include "api/job_service.h"

#include <algorithm>
#include <chrono>

#include "api/call_guard.h"
#include "api/error_details.h"
#include "api/paging.h"
#include "api/request_limits.h"
#include "api/resource_codec.h"
#include "codec/result_part_codec.h"
#include "codec/settings_codec.h"
#include "isocorr/settings/settings_schema.h"
#include "isocorr/util/error.h"
#include "service_error.h"

namespace isocorr::server {
using Kind = ServiceError::Kind;
using Clock = std::chrono::steady_clock;

namespace {

// Long waits wake up this often to notice a client that went away.
constexpr auto kPollInterval = std::chrono::milliseconds(500);
constexpr size_t kIndicesPerChunk = 256 * 1024;  // 1 MiB of int32, under the 4 MiB limit
constexpr size_t kReportBytesPerChunk = 1 << 20;

std::string require_job_id(const std::string& name) {
  require_bounded("name", name, kMaxNameBytes);
  const std::string id = job_id_from_name(name);
  if (id.empty())
    throw field_error("name", "INVALID_NAME", "job names look like jobs/{id}, got " + quoted_prefix(name));
  return id;
}

std::string require_mesh_digest(const std::string& name, const char* field) {
  require_bounded(field, name, kMaxNameBytes);
  const std::string digest = mesh_digest_from_name(name);
  if (digest.empty())
    throw field_error(field, "INVALID_NAME", std::string(field) + " must look like meshes/{sha256}, got " +
                                                 quoted_prefix(name));
  return digest;
}

// The request field an engine's settings error is about: "settings.<name>" when the message
// begins "setting <name>" (or "settings <name> + ..."), "settings.landmarks[i]" when it
// begins "landmarks[i]", else "settings".
std::string setting_field_of(const std::string& message) {
  if (message.rfind("landmarks[", 0) == 0) return "settings." + message.substr(0, message.find(']') + 1);
  for (const char* prefix : {"setting ", "settings "}) {
    if (message.rfind(prefix, 0) != 0) continue;
    const size_t begin = std::string(prefix).size();
    const size_t end = message.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_", begin);
    const std::string name = message.substr(begin, end - begin);
    if (find_setting(name)) return "settings." + name;
  }
  return "settings";
}

// The request's settings, checked here so that a refusal names the field.
MatchSettings require_valid_settings(const v1::MatchSettings& proto) {
  try {
    MatchSettings settings = api::settings_from_proto(proto);
    settings.validate();
    return settings;
  } catch (const InputError& e) {
    throw field_error(setting_field_of(e.what()), "INVALID_SETTING", e.what());
  }
}

// Ends a watch or wait that the server's shutdown interrupts: the job itself is kept.
[[noreturn]] void server_stopping(const std::string& name) {
  throw DetailedError(Kind::kUnavailable, "SERVER_STOPPING", "", "the server is stopping (" + name + " is kept)");
}

// The caller's deadline on the steady clock (far future when it set none).
Clock::time_point call_deadline(const grpc::ServerContext& context) {
  const auto remaining = context.deadline() - std::chrono::system_clock::now();
  if (remaining > std::chrono::hours(24 * 365)) return Clock::time_point::max();
  return Clock::now() + std::chrono::duration_cast<Clock::duration>(remaining);
}

template <typename T, typename Setter>
bool stream_elements(grpc::ServerWriter<v1::ResultChunk>& writer, v1::ResultPart part, const std::vector<T>& values,
                     Setter add) {
  size_t offset = 0;
  do {
    v1::ResultChunk chunk;
    chunk.set_part(part);
    chunk.set_offset(static_cast<int64_t>(offset));
    chunk.set_total(static_cast<int64_t>(values.size()));
    const size_t end = std::min(values.size(), offset + kIndicesPerChunk);
    for (size_t i = offset; i < end; ++i) add(chunk, values[i]);
    if (!writer.Write(chunk)) return false;
    offset = end;
  } while (offset < values.size());
  return true;
}

}  // namespace

grpc::Status JobServiceImpl::CreateMatchJob(grpc::ServerContext* context, const v1::CreateMatchJobRequest* request,
                                            v1::Job* response) {
  return guarded_call("CreateMatchJob", *context, auth_, [&](const CallInfo& call) {
    const std::string source = require_mesh_digest(request->source_mesh(), "source_mesh");
    const std::string target = require_mesh_digest(request->target_mesh(), "target_mesh");
    const MatchSettings settings = require_valid_settings(request->settings());
    *response = job_to_proto(jobs_.create(source, target, settings, call.request_id));
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::GetJob(grpc::ServerContext* context, const v1::GetJobRequest* request,
                                    v1::Job* response) {
  return guarded_call("GetJob", *context, auth_, [&](const CallInfo&) {
    *response = job_to_proto(jobs_.get(require_job_id(request->name())));
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::ListJobs(grpc::ServerContext* context, const v1::ListJobsRequest* request,
                                      v1::ListJobsResponse* response) {
  return guarded_call("ListJobs", *context, auth_, [&](const CallInfo&) {
    const std::vector<JobRecord> jobs = jobs_.list();
    response->set_next_page_token(fill_page(*response->mutable_jobs(), jobs.size(), request->page_size(),
                                            request->page_token(), [&](size_t i) { return job_to_proto(jobs[i]); }));
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::CancelJob(grpc::ServerContext* context, const v1::CancelJobRequest* request,
                                       v1::Job* response) {
  return guarded_call("CancelJob", *context, auth_, [&](const CallInfo&) {
    *response = job_to_proto(jobs_.cancel(require_job_id(request->name())));
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::WaitJob(grpc::ServerContext* context, const v1::WaitJobRequest* request,
                                     v1::Job* response) {
  return guarded_call("WaitJob", *context, auth_, [&](const CallInfo&) {
    const std::string id = require_job_id(request->name());
    Clock::time_point deadline = call_deadline(*context);
    if (request->has_timeout() && (request->timeout().seconds() > 0 || request->timeout().nanos() > 0)) {
      const auto timeout = std::chrono::seconds(request->timeout().seconds()) +
                           std::chrono::nanoseconds(request->timeout().nanos());
      deadline = std::min(deadline, Clock::now() + std::chrono::duration_cast<Clock::duration>(timeout));
    }
    JobRecord job = jobs_.get(id);
    while (!is_final(job.state) && Clock::now() < deadline && !context->IsCancelled()) {
      if (stopping_) server_stopping(request->name());
      job = jobs_.wait_for_change(id, job.version, std::min(deadline, Clock::now() + kPollInterval));
    }
    *response = job_to_proto(job);  // AIP-151: not done yet is a normal answer
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::WatchJob(grpc::ServerContext* context, const v1::WatchJobRequest* request,
                                      grpc::ServerWriter<v1::Job>* writer) {
  return guarded_call("WatchJob", *context, auth_, [&](const CallInfo&) {
    const std::string id = require_job_id(request->name());
    JobRecord job = jobs_.get(id);
    if (!writer->Write(job_to_proto(job))) return grpc::Status::OK;
    while (!is_final(job.state)) {
      if (context->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "watch cancelled by the client");
      if (stopping_) server_stopping(request->name());
      const uint64_t seen = job.version;
      job = jobs_.wait_for_change(id, seen, Clock::now() + kPollInterval);
      if (job.version != seen && !writer->Write(job_to_proto(job))) return grpc::Status::OK;
    }
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::DownloadResult(grpc::ServerContext* context, const v1::DownloadResultRequest* request,
                                            grpc::ServerWriter<v1::ResultChunk>* writer) {
  return guarded_call("DownloadResult", *context, auth_, [&](const CallInfo&) {
    const std::string id = require_job_id(request->name());
    const JobRecord job = jobs_.get(id);
    if (job.state != JobState::kSucceeded)
      throw DetailedError(Kind::kFailedPrecondition, "JOB_NOT_SUCCEEDED", "",
                          "job " + request->name() + " is " + job_state_name(job.state) +
                              "; results exist only for SUCCEEDED jobs");
    std::vector<ResultPart> parts;
    for (const int value : request->parts()) {
      const std::optional<ResultPart> part = api::result_part_from_proto(value);
      if (!part) throw field_error("parts", "UNKNOWN_RESULT_PART", "unknown result part " + std::to_string(value));
      parts.push_back(*part);
    }
    // All parts: those the result has (one stored before precise maps lacks them).
    const bool all_parts = parts.empty();
    if (all_parts) parts.assign(kAllResultParts.begin(), kAllResultParts.end());
    const ResultReader& results = jobs_.results();
    auto add_index = [](v1::ResultChunk& chunk, int value) { chunk.add_indices(value); };
    auto add_value = [](v1::ResultChunk& chunk, float value) { chunk.add_values(value); };
    auto add_point = [](v1::ResultChunk& chunk, const SurfacePoint& point) {
      chunk.add_indices(point.face);
      for (const float weight : point.weights) chunk.add_values(weight);
    };
    for (const ResultPart part : parts) {
      const v1::ResultPart proto_part = api::result_part_to_proto(part);
      bool written = true;
      switch (part) {
        case ResultPart::kForwardMap:
        case ResultPart::kReverseMap:
          written = stream_elements(*writer, proto_part, results.read_map(job, part), add_index);
          break;
        case ResultPart::kForwardConfidence:
        case ResultPart::kReverseConfidence:
          written = stream_elements(*writer, proto_part, results.read_confidence(job, part), add_value);
          break;
        case ResultPart::kForwardPrecise:
        case ResultPart::kReversePrecise: {
          PreciseMap points;
          try {
            points = results.read_precise(job, part);
          } catch (const PartNotStored&) {
            if (all_parts) continue;
            throw;
          }
          written = stream_elements(*writer, proto_part, points, add_point);
          break;
        }
        case ResultPart::kReport: {
          const std::string report = results.read_report(job);
          for (size_t offset = 0; written && (offset < report.size() || offset == 0);
               offset += kReportBytesPerChunk) {
            v1::ResultChunk chunk;
            chunk.set_part(proto_part);
            chunk.set_offset(static_cast<int64_t>(offset));
            chunk.set_total(static_cast<int64_t>(report.size()));
            chunk.set_data(report.substr(offset, kReportBytesPerChunk));
            written = writer->Write(chunk);
            if (report.empty()) break;
          }
          break;
        }
      }
      if (!written) return grpc::Status(grpc::StatusCode::CANCELLED, "client went away");
    }
    return grpc::Status::OK;
  });
}

}  // namespace isocorr::server
