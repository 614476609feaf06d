#include "jobs/job_execution.h"

#include <chrono>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/output/match_report.h"

namespace isocorr::server {
namespace {

// Preprocessing either mesh takes the first fifth of the progress bar, the match the rest.
constexpr double kPreprocessShare = 0.1;

ShapeCache::ShapePtr cached_shape(const std::string& digest, const MeshInfo& info, const PreprocessOptions& options,
                                  MeshStore& meshes, ShapeCache& cache, const JobControl& control) {
  JobControl build_control;  // cancellation only: progress belongs to the job that asked
  build_control.cancel_requested = control.cancel_requested;
  const std::string key = digest + "|" + options.key();
  for (;;) {
    try {
      return cache.get_or_build(key, [&] {
        const LoadedMesh loaded = parse_mesh(meshes.read_bytes(digest), info.filename);
        return PreprocessedShape::build(loaded.mesh, options, build_control);
      });
    } catch (const Cancelled&) {
      // The build we waited on belonged to a job that was cancelled; ours was not, so build.
      control.check_cancelled();
    }
  }
}

}  // namespace

ExecutedJob execute_match_job(const JobRecord& job, MeshStore& meshes, ShapeCache& cache, const JobControl& control) {
  job.settings.validate();
  PreprocessOptions options = job.settings.preprocess;
  options.threads = job.settings.threads;  // as match_meshes does
  const auto source_info = meshes.get(job.source_digest), target_info = meshes.get(job.target_digest);
  if (!source_info || !target_info)
    throw InputError("mesh meshes/" + (source_info ? job.target_digest : job.source_digest) +
                     " was deleted before the job ran");

  std::vector<StageTiming> timings;
  auto clock = std::chrono::steady_clock::now();
  auto lap = [&](const char* stage) {
    const auto now = std::chrono::steady_clock::now();
    timings.push_back({stage, std::chrono::duration<double>(now - clock).count()});
    clock = now;
  };
  control.report({"preprocess-source", 0, 0, 0.0});
  const auto source = cached_shape(job.source_digest, *source_info, options, meshes, cache, control);
  lap("preprocess-source");
  control.report({"preprocess-target", 0, 0, kPreprocessShare});
  const auto target = cached_shape(job.target_digest, *target_info, options, meshes, cache, control);
  lap("preprocess-target");

  JobControl match_control;
  match_control.cancel_requested = control.cancel_requested;
  match_control.on_progress = [&](const Progress& p) {
    Progress scaled = p;
    scaled.fraction = 2 * kPreprocessShare + (1 - 2 * kPreprocessShare) * p.fraction;
    control.report(scaled);
  };
  MatchResult result = match_shapes(*source, *target, job.settings, match_control);
  result.timings.insert(result.timings.begin(), timings.begin(), timings.end());

  ExecutedJob executed;
  JobSummary& s = executed.summary;
  s.source_vertices = static_cast<int>(result.forward.size());
  s.target_vertices = static_cast<int>(result.reverse.size());
  s.diso = result.diso;
  s.diso_max = result.diso_max;
  s.dense_orientation = result.dense_orientation;
  s.level0_maps = static_cast<int>(result.level0.size());
  s.tracked_maps = static_cast<int>(result.tracked.size());
  s.chosen_level0_rank = result.tracked.empty() ? 0 : result.tracked[result.chosen].level0_rank;
  s.timings = result.timings;
  s.notes = result.notes;
  executed.files.report_json = match_report_json(result, job.settings);
  executed.files.forward = std::move(result.forward);
  executed.files.reverse = std::move(result.reverse);
  executed.files.forward_confidence = std::move(result.forward_confidence);
  executed.files.reverse_confidence = std::move(result.reverse_confidence);
  return executed;
}

}  // namespace isocorr::server
