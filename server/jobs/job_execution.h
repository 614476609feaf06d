// What a worker does for one job: the engine's pipeline, with the shapes coming from the
// mesh store through the shared shape cache. Nothing else: the pipeline is core's.
#pragma once

#include "isocorr/matching/pipeline.h"
#include "jobs/shape_cache.h"
#include "storage/job_record.h"
#include "storage/mesh_store.h"

namespace isocorr::server {

// The shapes of one job: each read from the store and preprocessed once per cache key,
// whichever job asks first; concurrent jobs wait for the same build.
class CachedShapeProvider : public ShapeProvider {
 public:
  CachedShapeProvider(const JobRecord& job, MeshStore& meshes, ShapeCache& cache)
      : job_(job), meshes_(meshes), cache_(cache) {}
  std::shared_ptr<const PreprocessedShape> shape(ShapeRole role, const PreprocessOptions& options,
                                                 const JobControl& control) override;

 private:
  const JobRecord& job_;
  MeshStore& meshes_;
  ShapeCache& cache_;
};

// Throws InputError (unusable mesh or settings, or a mesh deleted before the job ran),
// Cancelled (control's flag), ServiceError(kDataLoss) for a corrupted stored mesh, or
// anything else for internal failures.
MatchResult execute_match_job(const JobRecord& job, MeshStore& meshes, ShapeCache& cache, const JobControl& control);

}  // namespace isocorr::server
