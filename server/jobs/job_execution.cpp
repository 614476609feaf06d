#include "jobs/job_execution.h"

#include <spdlog/spdlog.h>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/output/match_report.h"
#include "isocorr/util/error.h"

namespace isocorr::server {

std::shared_ptr<const PreprocessedShape> CachedShapeProvider::shape(ShapeRole role, const PreprocessOptions& options,
                                                                    const JobControl& control) {
  const std::string& digest = role == ShapeRole::kSource ? job_.source_digest : job_.target_digest;
  if (!meshes_.describe(digest)) throw InputError("mesh meshes/" + digest + " was deleted before the job ran");
  // Progress belongs to the job that asked, not to the others waiting for the same build.
  const JobControl build_control = control.cancellation_only();
  const std::string key = digest + "|" + options.key();
  for (;;) {
    try {
      return cache_.get_or_build(key, [&] {
        // Read here, when the cache builds, so the bytes are checked against the digest
        // (ServiceError kDataLoss) before any shape is made of them.
        const MeshRepository::StoredMesh stored = meshes_.read(digest);
        const LoadedMesh loaded = parse_mesh(stored.bytes, stored.info.filename);
        return PreprocessedShape::build(loaded.mesh, options, build_control);
      });
    } catch (const Cancelled&) {
      // The build we waited on belonged to a job that was cancelled or ran out of time; if
      // ours was not, build.
      control.check_cancelled();
    }
  }
}

MatchResult execute_match_job(const JobRecord& job, MeshRepository& meshes, ShapeCache& cache, const JobControl& control) {
  CachedShapeProvider shapes(job, meshes, cache);
  MatchResult result = run_match(shapes, job.settings, control);
  // The report names the uploaded files it was made from (meshes/{sha256} on the server).
  auto input = [&](const std::string& digest) {
    const auto info = meshes.describe(digest);
    return ReportInput{info ? info->filename : "meshes/" + digest, digest};
  };
  result.output.report_json =
      report_with_inputs(result.output.report_json, input(job.source_digest), input(job.target_digest));
  return result;
}

JobControl::Clock::time_point run_deadline(std::chrono::seconds limit) {
  return limit.count() > 0 ? JobControl::Clock::now() + limit : JobControl::Clock::time_point::max();
}

ErrorCode error_code_for(ServiceError::Kind kind) {
  using Kind = ServiceError::Kind;
  switch (kind) {
    case Kind::kDataLoss: return ErrorCode::kDataLoss;
    case Kind::kResourceExhausted: return ErrorCode::kResourceExhausted;
    case Kind::kNotFound: return ErrorCode::kNotFound;
    case Kind::kInvalidArgument: return ErrorCode::kInvalidArgument;
    default: return ErrorCode::kInternal;
  }
}

JobRecord run_to_conclusion(const JobRecord& job, MeshRepository& meshes, ShapeCache& cache, const JobControl& control,
                            const std::function<void(const MatchOutput&)>& store_result) {
  JobRecord final_record = job;
  try {
    const MatchResult result = execute_match_job(job, meshes, cache, control);
    try {
      store_result(result.output);
    } catch (const ServiceError& e) {
      throw ServiceError(e.kind(), std::string("cannot store the result: ") + e.what());
    }
    final_record.state = JobState::kSucceeded;
    final_record.summary = result.summary();
    final_record.progress = {"done", 0, 0, 1.0};
    for (const auto& warning : result.messages.warnings) spdlog::warn("[{}] {}", job_tag(job), warning);
    spdlog::info("[{}] succeeded: D_iso {:.4f}", job_tag(job), final_record.summary.diso);
  } catch (const DeadlineExceeded&) {
    final_record.state = JobState::kFailed;
    final_record.error_code = ErrorCode::kDeadlineExceeded;
    final_record.error_message = "the job ran past the server's time limit for a job (isocorr-server --job-time-limit)";
    spdlog::warn("[{}] failed: {}", job_tag(job), final_record.error_message);
  } catch (const Cancelled&) {
    throw;
  } catch (const InputError& e) {
    final_record.state = JobState::kFailed;
    final_record.error_code = ErrorCode::kInvalidArgument;
    final_record.error_message = e.what();
    spdlog::warn("[{}] failed: {}", job_tag(job), e.what());
  } catch (const ServiceError& e) {  // a corrupted mesh (DATA_LOSS), a full disk
    final_record.state = JobState::kFailed;
    final_record.error_code = error_code_for(e.kind());
    final_record.error_message = e.what();
    spdlog::error("[{}] failed: {}", job_tag(job), e.what());
  } catch (const std::exception& e) {
    final_record.state = JobState::kFailed;
    final_record.error_code = ErrorCode::kInternal;
    final_record.error_message = std::string("internal error: ") + e.what();
    spdlog::error("[{}] failed: {}", job_tag(job), e.what());
  }
  return final_record;
}

}  // namespace isocorr::server
