#include "jobs/job_coordinator.h"

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
  for (const std::string* digest : {&source_digest, &target_digest})
    if (!meshes.describe(*digest))
      throw ServiceError(Kind::kNotFound, "no mesh meshes/" + *digest + " on this server; upload it first");
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
