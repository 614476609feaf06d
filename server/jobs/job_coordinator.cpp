#include "jobs/job_coordinator.h"

#include "isocorr/transfer/landmarks.h"
#include "isocorr/util/error.h"
#include "service_error.h"

namespace isocorr::server {
using Kind = ServiceError::Kind;

void JobCoordinator::check_new_job(MeshRepository& meshes, const std::string& source_digest,
                                   const std::string& target_digest, const MatchSettings& settings) {
  try {
    settings.validate();
  } catch (const InputError& e) {
    throw ServiceError(Kind::kInvalidArgument, std::string("settings: ") + e.what());
  }
  int vertices[2] = {0, 0};
  for (int side = 0; side < 2; ++side) {
    const std::string& digest = side == 0 ? source_digest : target_digest;
    const auto info = meshes.describe(digest);
    if (!info) throw ServiceError(Kind::kNotFound, "no mesh meshes/" + digest + " on this server; upload it first");
    vertices[side] = info->vertex_count;
  }
  // Landmarks name vertices of the files, whose counts the store knows.
  try {
    validate_landmarks(settings.landmarks, vertices[0], vertices[1]);
  } catch (const InputError& e) {
    throw ServiceError(Kind::kInvalidArgument, std::string("settings: ") + e.what());
  }
}

JobRecord JobCoordinator::new_job(const std::string& source_digest, const std::string& target_digest,
                                  const MatchSettings& settings, const std::string& request_id) {
  JobRecord record;
  record.id = new_job_id();
  record.source_digest = source_digest;
  record.target_digest = target_digest;
  record.settings = settings;
  record.created_by_request = request_id;
  record.create_time_ms = now_ms();
  return record;
}

ServiceError JobCoordinator::queue_full(size_t queued) {
  return ServiceError(Kind::kResourceExhausted, std::to_string(queued) +
                                                    " jobs are queued, the server's limit (--max-queued-jobs); "
                                                    "retry when some have finished");
}

}  // namespace isocorr::server
