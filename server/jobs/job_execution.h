// What a worker does for one job: the meshes from the store, their preprocessing from the
// shared cache, the engine's match, and the result in the form the journal stores.
#pragma once

#include <string>

#include "isocorr/matching/matcher.h"
#include "isocorr/util/progress.h"
#include "jobs/job_record.h"
#include "jobs/shape_cache.h"
#include "storage/job_journal.h"
#include "storage/mesh_store.h"

namespace isocorr::server {

struct ExecutedJob {
  JobResultFiles files;
  JobSummary summary;
};

// Throws InputError (unusable mesh or settings), Cancelled (control's flag), ServiceError
// (mesh deleted) or anything else for internal failures.
ExecutedJob execute_match_job(const JobRecord& job, MeshStore& meshes, ShapeCache& cache, const JobControl& control);

}  // namespace isocorr::server
