#include "isocorr/matching/matcher.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>

#include "isocorr/refinement/refinement.h"
#include "isocorr/transfer/landmarks.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
Eigen::MatrixXd sample_distances(const PreprocessedShape& shape, int count) {
  std::vector<int> first(count);
  std::iota(first.begin(), first.end(), 0);
  return sample_distances(shape, first);
}

Eigen::MatrixXd sample_distances(const PreprocessedShape& shape, const std::vector<int>& samples) {
  const int count = static_cast<int>(samples.size());
  Eigen::MatrixXd d(count, count);
  for (int i = 0; i < count; ++i)
    for (int j = 0; j < count; ++j)
      // Symmetrise: fast marching is not exactly symmetric.
      d(i, j) = 0.5 * (shape.sample_field(samples[i], samples[j]) + shape.sample_field(samples[j], samples[i]));
  return d;
}

// Orientation rule: a mirrored map, or one with a limb pair swapped, reverses the
// handedness of part of the surface, so only maps whose orientation agreement is within
// `orientation_margin` of the best one compete. Among them D_iso decides, lowered by
// `orientation_weight` per unit of agreement: a human's front/back-turned map keeps
// orientation too and comes within a few per cent of the true map's D_iso. Returns all
// tracked maps, best first: the competing ones by score, then the rest by score.
std::vector<int> rank_tracked(const std::vector<TrackedMap>& tracked, const MatchSettings& settings) {
  double best_orientation = 0;
  for (const auto& t : tracked) best_orientation = std::max(best_orientation, t.orientation);
  const bool use_orientation = settings.selection == SelectionRule::kOrientationThenDistortion &&
                               best_orientation >= settings.orientation_threshold;
  const double weight = use_orientation ? settings.orientation_weight : 0.0;
  auto score = [&](const TrackedMap& t) { return t.diso - weight * t.orientation; };
  auto competes = [&](const TrackedMap& t) {
    return !use_orientation || t.orientation >= best_orientation - settings.orientation_margin;
  };
  std::vector<int> order(tracked.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    if (competes(tracked[a]) != competes(tracked[b])) return competes(tracked[a]);
    return score(tracked[a]) < score(tracked[b]);
  });
  return order;
}

namespace {

// Drops the level-0 maps that disagree with the landmarks (transfer/landmarks.h), then keeps
// the best max_level0_maps. A landmark pair is one more pair of the map, so it must agree
// with the map's samples as well as they must agree with one another: its disagreement, a
// d_iso against the samples, must stay under max_level0_diso, the bound on the map's own
// D_iso. A map that the landmarks agree with scores about its D_iso; on a symmetric shape
// its turned or mirrored twin scores 0.2-0.4 with a landmark on a limb.
void drop_maps_off_landmarks(const PreprocessedShape& source, const PreprocessedShape& target,
                             const LandmarkGeometry& landmarks, const MatchSettings& settings,
                             std::vector<Level0Map>& maps, MatchResult& result) {
  std::vector<double> disagreement(maps.size());
  for (size_t i = 0; i < maps.size(); ++i) {
    std::vector<std::pair<int, int>> pairs;
    for (size_t a = 0; a < maps[i].target_of.size(); ++a)
      pairs.emplace_back(source.sample_vertex(static_cast<int>(a)), target.sample_vertex(maps[i].target_of[a]));
    disagreement[i] = landmarks.disagreement(pairs);
  }
  const Level0Drop drop = drop_level0_maps(maps, disagreement, settings.max_level0_diso);
  if (maps.size() > static_cast<size_t>(settings.max_level0_maps)) maps.resize(settings.max_level0_maps);
  LandmarkDiagnostics& diagnostics = result.diagnostics.landmarks;
  diagnostics.level0_dropped = drop.dropped;
  diagnostics.level0_none_agreed = drop.none_agreed;
  if (drop.none_agreed)
    result.messages.warnings.push_back(
        "landmarks: no level-0 map agrees with them (disagreement under max_level0_diso = " +
        std::to_string(settings.max_level0_diso) + "); the least disagreeing one was kept");
  result.messages.notes.push_back("landmarks: " + std::to_string(drop.dropped) +
                                  " level-0 maps dropped for disagreeing with them");
}

// The level-0 search over M source and M' target samples; returns M.
int search_level0_maps(const PreprocessedShape& source, const PreprocessedShape& target,
                       const MatchSettings& settings, const LandmarkGeometry& landmarks, int threads,
                       MatchResult& result) {
  Level0Diagnostics& level0 = result.diagnostics.level0;
  const int requested_m = settings.level0_samples > 0
                              ? settings.level0_samples
                              : std::clamp(static_cast<int>(source.saliency().extremities.size()), 5, 7);
  const int m = std::min(requested_m, source.num_level0_samples());
  const int m_prime = std::min(m + settings.level0_extra_targets, target.num_level0_samples());
  if (m < 3 || m_prime < m)
    throw InputError("too few level-0 samples (" + std::to_string(m) + " on the source, " +
                     std::to_string(m_prime) + " on the target); lower the level-0 radius");
  // With landmarks every map under the threshold is listed: the cap applies to those left.
  level0.maps = search_level0(sample_distances(source, m), sample_distances(target, m_prime),
                              settings.max_level0_diso,
                              landmarks.empty() ? settings.max_level0_maps : std::numeric_limits<int>::max(), threads);
  if (level0.maps.empty())
    throw InputError("no level-0 map has D_iso under " + std::to_string(settings.max_level0_diso) +
                     ": the shapes are far from isometric (raise max_level0_diso to try anyway)");
  if (!landmarks.empty()) drop_maps_off_landmarks(source, target, landmarks, settings, level0.maps, result);
  return m;
}

// The N best level-0 maps tracked to level K1 = `levels`, in parallel (each writes its own
// slot); N by the jump rule within the settings' bounds.
std::vector<TrackedMap> track_level0_maps(const PreprocessedShape& source, const PreprocessedShape& target,
                                          const MatchSettings& settings, int m, int levels, int threads,
                                          Level0Diagnostics& level0, const JobControl& control) {
  level0.tracked_by_jump_rule = jump_rule_count(level0.maps);
  const int tracked_count = std::min<int>(
      level0.maps.size(), std::clamp(level0.tracked_by_jump_rule, settings.min_tracked, settings.max_tracked));
  std::vector<TrackedMap> tracked(tracked_count);
  const TrackingOptions& tracking = settings.tracking;
  const TrackingPlan plan = plan_tracking(source, m, levels, tracking);
  std::atomic<int> done{0};
  parallel_for(tracked_count, threads, [&](int i, int) {
    tracked[i] = track_map(source, target, plan, level0.maps[i], i, tracking, control);
    const int finished = ++done;
    control.report({"tracking", levels, levels + 1, 0.1 + 0.6 * finished / tracked_count});
  });
  return tracked;
}

// What the refinement's repairs and polishes did, for the report's notes.
void note_refinement(const MatchSettings& settings, const RefinedMatch& refined, std::vector<std::string>& notes) {
  if (settings.outlier_repair)
    notes.push_back("outlier repair: " + std::to_string(refined.repair.moved) + " of " +
                    std::to_string(refined.repair.flagged) + " flagged vertices placed again (" +
                    std::to_string(refined.repair.anchors) + " anchors)");
  if (settings.rigidity.mirror_repair && settings.rigidity.iterations > 0) {
    const MirrorRepair& chosen = refined.mirror_repair_chosen;
    const MirrorRepair& last = refined.mirror_repair;
    notes.push_back("mirror repair of the chosen map: " + std::to_string(chosen.segments) +
                    " mirrored segments held at both ends unfolded before its spectral polish (" +
                    std::to_string(chosen.reversed_vertices) + " vertices with reversed rings); after it " +
                    std::to_string(last.segments) + " placed again" +
                    (last.segments == 0 ? ""
                     : last.kept        ? ", kept (lower rigidity energy)"
                                        : ", not kept (higher rigidity energy)") +
                    " (" + std::to_string(last.reversed_vertices) + " vertices with reversed rings)");
  }
  if (settings.refine_passes > 0)
    notes.push_back("the chosen map refined again from itself " + std::to_string(settings.refine_passes) +
                    (settings.refine_passes == 1 ? " time" : " times"));
  if (settings.rigidity_final_iterations > 0) {
    char note[160];
    std::snprintf(note, sizeof note,
                  "final rigidity polish (%d iterations per weight): curvature disagreement %.4f -> %.4f, %s",
                  settings.rigidity_final_iterations, refined.final_polish.curvature_before,
                  refined.final_polish.curvature_after, refined.final_polish.kept ? "kept" : "not kept");
    notes.push_back(note);
  }
}

// The refinement's dense map, with its diagnostics, step timings and notes kept in `result`;
// the chosen tracked map becomes the refined winner's.
DenseMap refine(const PreprocessedShape& source, const PreprocessedShape& target, const MatchSettings& settings,
                const LandmarkGeometry& landmarks, const std::vector<int>& ranked, MatchResult& result,
                const JobControl& control) {
  RefinedMatch refined =
      refine_and_choose(source, target, result.diagnostics.tracking.maps, ranked, settings, control, landmarks);
  note_refinement(settings, refined, result.messages.notes);
  RefinementDiagnostics& diagnostics = result.diagnostics.refinement;
  diagnostics.screened = std::move(refined.screened);
  diagnostics.candidates = std::move(refined.candidates);
  diagnostics.chosen = refined.chosen;
  diagnostics.why = std::move(refined.why);
  diagnostics.functional_map = std::move(refined.functional_map);
  result.timings.refine_steps = std::move(refined.timings);
  result.diagnostics.tracking.chosen = diagnostics.candidates[diagnostics.chosen].tracked_index;
  return std::move(refined.dense);
}

}  // namespace

DenseMap match_whole(const PreprocessedShape& source, const PreprocessedShape& target, const MatchSettings& settings,
                     MatchResult& result, const JobControl& control) {
  StageClock clock(result.timings.stages);
  const int levels = std::min(source.options().decision_level, target.options().decision_level);
  const int total_levels = levels + 1;  // levels 0..K1, then the dense level
  const int threads = resolve_thread_count(control.threads);

  control.report({"level0", 0, total_levels, 0.0});
  const LandmarkGeometry landmarks(source, target, settings.landmarks);
  const int m = search_level0_maps(source, target, settings, landmarks, threads, result);
  clock.finish("level0");

  TrackingDiagnostics& tracking = result.diagnostics.tracking;
  tracking.maps = track_level0_maps(source, target, settings, m, levels, threads, result.diagnostics.level0, control);
  const std::vector<int> ranked = rank_tracked(tracking.maps, settings);
  tracking.chosen = ranked.front();
  clock.finish("tracking");

  if (settings.refine == RefineMethod::kNone) {
    // The C2F dense level from the chosen map only.
    control.report({"dense", total_levels, total_levels, 0.7});
    DenseMap dense = compute_dense_map(source, target, tracking.maps[tracking.chosen].pairs, settings.dense, control);
    hold_landmarks(landmarks, dense, result);
    clock.finish("dense");
    return dense;
  }
  control.report({"refine", total_levels, total_levels, 0.7});
  DenseMap dense = refine(source, target, settings, landmarks, ranked, result, control);
  hold_landmarks(landmarks, dense, result);
  clock.finish("refine");
  return dense;
}

}  // namespace isocorr
