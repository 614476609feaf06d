#include "isocorr/pipeline/run_match.h"

#include <future>
#include <string>

#include "isocorr/output/match_report.h"
#include "isocorr/pipeline/match_shapes.h"

namespace isocorr {
namespace {

// Share of the progress bar taken by each side's preprocessing; the match has the rest.
// A cached shape makes its share pass at once.
constexpr double kPreprocessShare = 0.1;

// A numerical failure says which mesh it came from: the message is all a user sees.
std::shared_ptr<const PreprocessedShape> shape_naming_failures(ShapeProvider& shapes, ShapeRole role,
                                                               const PreprocessOptions& options,
                                                               const JobControl& control) {
  try {
    return shapes.shape(role, options, control);
  } catch (const NumericalError& e) {
    throw NumericalError(std::string(role == ShapeRole::kSource ? "source" : "target") + " mesh: " + e.what());
  }
}

}  // namespace

std::shared_ptr<const PreprocessedShape> MeshPairShapes::shape(ShapeRole role, const PreprocessOptions& options,
                                                               const JobControl& control) {
  const std::string key = (role == ShapeRole::kSource ? "source|" : "target|") + options.key();
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto found = built_.find(key);
    if (found != built_.end()) return found->second;
  }
  // Built outside the lock: run_match asks for both sides at once.
  auto shape = PreprocessedShape::build(role == ShapeRole::kSource ? source_ : target_, options, control);
  const std::lock_guard<std::mutex> lock(mutex_);
  return built_.emplace(key, std::move(shape)).first->second;
}

MatchResult run_match(ShapeProvider& shapes, const MatchSettings& settings, const JobControl& control) {
  settings.validate();
  const PreprocessOptions& options = settings.preprocess;
  // The one thread rule: the match's setting, 0 = all cores, for every stage below.
  JobControl run_control = control;
  run_control.threads = settings.threads;

  std::vector<StageTiming> timings;
  StageClock clock(timings);
  control.report({"preprocess-source", 0, 0, 0.0});
  // Both sides at once: each preprocessing runs its eigensolver on one thread beside its
  // geodesic work, so one side alone leaves a core idle for much of its time (michael0 ->
  // michael1, 52K vertices, 2 cores: 17.2 s one after the other, 14.6 s at once). The
  // target's stage then times only what is left of it.
  auto target_shape = std::async(std::launch::async, [&shapes, &options, &run_control] {
    return shape_naming_failures(shapes, ShapeRole::kTarget, options, run_control);
  });
  const auto source = shape_naming_failures(shapes, ShapeRole::kSource, options, run_control);
  clock.finish("preprocess-source");
  control.report({"preprocess-target", 0, 0, kPreprocessShare});
  const auto target = target_shape.get();
  clock.finish("preprocess-target");

  JobControl match_control = run_control.cancellation_only();
  match_control.on_progress = [&](const Progress& p) {
    Progress scaled = p;
    scaled.fraction = 2 * kPreprocessShare + (1 - 2 * kPreprocessShare) * p.fraction;
    control.report(scaled);
  };
  MatchResult result = match_shapes(*source, *target, settings, match_control);
  result.timings.stages.insert(result.timings.stages.begin(), timings.begin(), timings.end());
  result.output.report_json = match_report_json(result, settings);
  return result;
}

MatchResult match_meshes(const TriangleMesh& source, const TriangleMesh& target, const MatchSettings& settings,
                         const JobControl& control) {
  MeshPairShapes shapes(source, target);
  return run_match(shapes, settings, control);
}

}  // namespace isocorr
