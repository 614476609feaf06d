#include "jobs/job_execution.h"

#include "isocorr/mesh/mesh_io.h"

namespace isocorr::server {

std::shared_ptr<const PreprocessedShape> CachedShapeProvider::shape(ShapeRole role, const PreprocessOptions& options,
                                                                    const JobControl& control) {
  const std::string& digest = role == ShapeRole::kSource ? job_.source_digest : job_.target_digest;
  if (!meshes_.describe(digest)) throw InputError("mesh meshes/" + digest + " was deleted before the job ran");
  JobControl build_control;  // cancellation only: progress belongs to the job that asked
  build_control.cancel_requested = control.cancel_requested;
  const std::string key = digest + "|" + options.key();
  for (;;) {
    try {
      return cache_.get_or_build(key, [&] {
        // Read here, when the cache builds, so the bytes are checked against the digest
        // (ServiceError kDataLoss) before any shape is made of them.
        const MeshStore::StoredMesh stored = meshes_.read(digest);
        const LoadedMesh loaded = parse_mesh(stored.bytes, stored.info.filename);
        return PreprocessedShape::build(loaded.mesh, options, build_control);
      });
    } catch (const Cancelled&) {
      // The build we waited on belonged to a job that was cancelled; ours was not, so build.
      control.check_cancelled();
    }
  }
}

MatchResult execute_match_job(const JobRecord& job, MeshStore& meshes, ShapeCache& cache, const JobControl& control) {
  CachedShapeProvider shapes(job, meshes, cache);
  return run_match(shapes, job.settings, control);
}

}  // namespace isocorr::server
