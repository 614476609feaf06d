#include "isocorr/matching/matcher.h"

#include <algorithm>
#include <chrono>

#include "isocorr/matching/orientation.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

class StageClock {
 public:
  explicit StageClock(std::vector<StageTiming>& timings) : timings_(timings) {}
  void finish(const std::string& stage) {
    const auto now = std::chrono::steady_clock::now();
    timings_.push_back({stage, std::chrono::duration<double>(now - start_).count()});
    start_ = now;
  }

 private:
  std::vector<StageTiming>& timings_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

Eigen::MatrixXd sample_distances(const PreprocessedShape& shape, int count) {
  Eigen::MatrixXd d(count, count);
  for (int i = 0; i < count; ++i)
    for (int j = 0; j < count; ++j)
      // Symmetrise: fast marching is not exactly symmetric.
      d(i, j) = 0.5 * (shape.field(i, shape.sample_vertex(j)) + shape.field(j, shape.sample_vertex(i)));
  return d;
}

// Orientation rule: a mirrored map, or one with a limb pair swapped, reverses the
// handedness of part of the surface, so only maps whose orientation agreement is within
// `orientation_margin` of the best one compete. Among them D_iso decides, lowered by
// `orientation_weight` per unit of agreement: a human's front/back-turned map keeps
// orientation too and comes within a few per cent of the true map's D_iso.
int choose_tracked(const std::vector<TrackedMap>& tracked, const MatchSettings& settings) {
  double best_orientation = 0;
  for (const auto& t : tracked) best_orientation = std::max(best_orientation, t.orientation);
  const bool use_orientation = settings.selection == SelectionRule::kOrientationThenDistortion &&
                               best_orientation >= settings.orientation_threshold;
  const double weight = use_orientation ? settings.orientation_weight : 0.0;
  auto score = [&](const TrackedMap& t) { return t.diso - weight * t.orientation; };
  int chosen = -1;
  for (int i = 0; i < static_cast<int>(tracked.size()); ++i) {
    if (use_orientation && tracked[i].orientation < best_orientation - settings.orientation_margin) continue;
    if (chosen < 0 || score(tracked[i]) < score(tracked[chosen])) chosen = i;
  }
  return chosen;
}

}  // namespace

void MatchSettings::validate() const {
  if (level0_samples != 0 && (level0_samples < 3 || level0_samples > 10))
    throw InputError("level-0 sample count M must be 0 (automatic) or lie in [3, 10]");
  if (level0_extra_targets < 0 || level0_extra_targets > 3)
    throw InputError("extra level-0 target samples (M' - M) must lie in [0, 3]");
  if (std::max(level0_samples, 7) + level0_extra_targets > preprocess.max_level0_samples)
    throw InputError("M + (M' - M) exceeds the level-0 samples kept per mesh (" +
                     std::to_string(preprocess.max_level0_samples) + ")");
  if (max_level0_diso <= 0 || max_level0_diso > 1) throw InputError("max level-0 D_iso must lie in (0, 1]");
  if (max_level0_maps < 1) throw InputError("max level-0 maps must be at least 1");
  if (min_tracked < 1 || max_tracked < min_tracked) throw InputError("need 1 <= min tracked <= max tracked");
  if (orientation_threshold < 0 || orientation_threshold > 1)
    throw InputError("orientation threshold must lie in [0, 1]");
  if (orientation_margin < 0 || orientation_margin > 1)
    throw InputError("orientation margin must lie in [0, 1]");
  if (orientation_weight < 0 || orientation_weight > 1)
    throw InputError("orientation weight must lie in [0, 1]");
  if (tracking.anchor_cap < 3) throw InputError("anchor cap must be at least 3");
  if (tracking.trim_fraction < 0 || tracking.trim_fraction >= 0.9)
    throw InputError("trim fraction must lie in [0, 0.9)");
  if (tracking.window_factor <= 0) throw InputError("window factor must be positive");
  if (dense.anchor_count < 3) throw InputError("dense anchor count E must be at least 3");
  if (dense.outlier_fraction < 0 || dense.outlier_fraction >= 1)
    throw InputError("dense outlier fraction must lie in [0, 1)");
  if (dense.outlier_ratio < 1) throw InputError("dense outlier ratio must be at least 1");
}

MatchResult match_shapes(const PreprocessedShape& source, const PreprocessedShape& target,
                         const MatchSettings& settings, const JobControl& control) {
  settings.validate();
  MatchResult result;
  StageClock clock(result.timings);
  const int levels = std::min(source.options().decision_level, target.options().decision_level);
  const int total_levels = levels + 1;  // levels 0..K1, then the dense level

  // Level 0.
  control.report({"level0", 0, total_levels, 0.0});
  const int requested_m = settings.level0_samples > 0
                              ? settings.level0_samples
                              : std::clamp(static_cast<int>(source.saliency().extremities.size()), 5, 7);
  const int m = std::min(requested_m, source.num_level0_samples());
  const int m_prime = std::min(m + settings.level0_extra_targets, target.num_level0_samples());
  if (m < 3 || m_prime < m)
    throw InputError("too few level-0 samples (" + std::to_string(m) + " on the source, " +
                     std::to_string(m_prime) + " on the target); lower the level-0 radius");
  const int threads = resolve_thread_count(settings.threads);
  result.level0 = search_level0(sample_distances(source, m), sample_distances(target, m_prime),
                                settings.max_level0_diso, settings.max_level0_maps, threads);
  if (result.level0.empty())
    throw InputError("no level-0 map has D_iso under " + std::to_string(settings.max_level0_diso) +
                     ": the shapes are far from isometric (raise max_level0_diso to try anyway)");
  clock.finish("level0");

  // Tracking the N best level-0 maps to level K1, in parallel (each writes its own slot).
  result.tracked_by_jump_rule = jump_rule_count(result.level0);
  const int tracked_count = std::min<int>(
      result.level0.size(),
      std::clamp(result.tracked_by_jump_rule, settings.min_tracked, settings.max_tracked));
  result.tracked.resize(tracked_count);
  TrackingOptions tracking = settings.tracking;
  tracking.threads = 1;
  std::atomic<int> done{0};
  parallel_for(tracked_count, threads, [&](int i, int) {
    result.tracked[i] = track_map(source, target, result.level0[i], i, tracking, control);
    const int finished = ++done;
    control.report({"tracking", levels, total_levels, 0.1 + 0.6 * finished / tracked_count});
  });
  result.chosen = choose_tracked(result.tracked, settings);
  clock.finish("tracking");

  // Dense level from the chosen map only.
  control.report({"dense", total_levels, total_levels, 0.7});
  DenseOptions dense_options = settings.dense;
  dense_options.threads = threads;
  const DenseMap dense =
      compute_dense_map(source, target, result.tracked[result.chosen].pairs, dense_options, control);
  clock.finish("dense");

  // Back to the files' numbering.
  const CleanMesh& sc = source.clean();
  const CleanMesh& tc = target.clean();
  result.forward.resize(sc.input_to_clean.size());
  result.forward_confidence.resize(sc.input_to_clean.size());
  for (size_t i = 0; i < sc.input_to_clean.size(); ++i) {
    const int c = sc.input_to_clean[i];
    result.forward[i] = tc.clean_to_input[dense.forward[c]];
    result.forward_confidence[i] = dense.forward_diso[c];
  }
  result.reverse.resize(tc.input_to_clean.size());
  result.reverse_confidence.resize(tc.input_to_clean.size());
  for (size_t i = 0; i < tc.input_to_clean.size(); ++i) {
    const int c = tc.input_to_clean[i];
    result.reverse[i] = sc.clean_to_input[dense.reverse[c]];
    result.reverse_confidence[i] = dense.reverse_diso[c];
  }
  double sum = 0, worst = 0;
  for (float d : dense.forward_diso) sum += d, worst = std::max(worst, static_cast<double>(d));
  result.diso = sum / std::max<size_t>(1, dense.forward_diso.size());
  result.diso_max = worst;
  result.dense_orientation = dense_orientation_agreement(source.mesh(), source.normals(), target.mesh(),
                                                         target.normals(), dense.forward);
  for (const auto& note : sc.repairs) result.notes.push_back("source: " + note);
  for (const auto& note : tc.repairs) result.notes.push_back("target: " + note);
  control.report({"done", total_levels, total_levels, 1.0});
  return result;
}

MatchResult match_meshes(const TriangleMesh& source, const TriangleMesh& target,
                         const MatchSettings& settings, const JobControl& control) {
  settings.validate();
  std::vector<StageTiming> timings;
  StageClock clock(timings);
  PreprocessOptions options = settings.preprocess;
  options.threads = settings.threads;
  control.report({"preprocess-source", 0, 0, 0.0});
  const auto source_shape = PreprocessedShape::build(source, options, control);
  clock.finish("preprocess-source");
  control.report({"preprocess-target", 0, 0, 0.0});
  const auto target_shape = PreprocessedShape::build(target, options, control);
  clock.finish("preprocess-target");
  MatchResult result = match_shapes(*source_shape, *target_shape, settings, control);
  result.timings.insert(result.timings.begin(), timings.begin(), timings.end());
  return result;
}

}  // namespace isocorr
