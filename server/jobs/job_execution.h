// What a worker does for one job: the engine's pipeline, with the shapes coming from the
// mesh store through the shared shape cache. Nothing else: the pipeline is core's.
#pragma once

#include <functional>

#include "isocorr/pipeline/run_match.h"
#include "jobs/shape_cache.h"
#include "storage/job_record.h"
#include "service_error.h"
#include "storage/mesh_repository.h"

namespace isocorr::server {

// The shapes of one job: each read from the store and preprocessed once per cache key,
// whichever job asks first; concurrent jobs wait for the same build.
class CachedShapeProvider : public ShapeProvider {
 public:
  CachedShapeProvider(const JobRecord& job, MeshRepository& meshes, ShapeCache& cache)
      : job_(job), meshes_(meshes), cache_(cache) {}
  std::shared_ptr<const PreprocessedShape> shape(ShapeRole role, const PreprocessOptions& options,
                                                 const JobControl& control) override;

 private:
  const JobRecord& job_;
  MeshRepository& meshes_;
  ShapeCache& cache_;
};

// Throws InputError (unusable mesh or settings, or a mesh deleted before the job ran),
// Cancelled (control's flag), ServiceError(kDataLoss) for a corrupted stored mesh, or
// anything else for internal failures.
MatchResult execute_match_job(const JobRecord& job, MeshRepository& meshes, ShapeCache& cache, const JobControl& control);

// When a run that starts now must end, for a time limit of `limit` (0: never).
JobControl::Clock::time_point run_deadline(std::chrono::seconds limit);

// The job's error code for a store's ServiceError.
ErrorCode error_code_for(ServiceError::Kind kind);

// Runs `job` and returns its final record: SUCCEEDED with the summary once `store_result`
// has stored the output, or FAILED with the error code and reason (end time not yet set;
// DEADLINE_EXCEEDED past control's deadline). Cancelled propagates: the caller knows whether
// a cancel or a shutdown asked for it.
JobRecord run_to_conclusion(const JobRecord& job, MeshRepository& meshes, ShapeCache& cache, const JobControl& control,
                            const std::function<void(const MatchOutput&)>& store_result);

}  // namespace isocorr::server
