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

}  // namespace isocorr::server
