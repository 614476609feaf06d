#include "isocorr/matching/matcher.h"

#include <algorithm>
#include <cstdio>

#include <numeric>

#include "isocorr/matching/orientation.h"
#include "isocorr/partial/part_matching.h"
#include "isocorr/refinement/refinement.h"
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

// Complete shapes: level 0, flip tracking, then the C2F dense level or refinement.
DenseMap match_complete(const PreprocessedShape& source, const PreprocessedShape& target,
                        const MatchSettings& settings, MatchResult& result, const JobControl& control) {
  StageClock clock(result.timings.stages);
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
  result.diagnostics.level0.maps = search_level0(sample_distances(source, m), sample_distances(target, m_prime),
                                settings.max_level0_diso, settings.max_level0_maps, threads);
  if (result.diagnostics.level0.maps.empty())
    throw InputError("no level-0 map has D_iso under " + std::to_string(settings.max_level0_diso) +
                     ": the shapes are far from isometric (raise max_level0_diso to try anyway)");
  clock.finish("level0");

  // Tracking the N best level-0 maps to level K1, in parallel (each writes its own slot).
  result.diagnostics.level0.tracked_by_jump_rule = jump_rule_count(result.diagnostics.level0.maps);
  const int tracked_count = std::min<int>(
      result.diagnostics.level0.maps.size(),
      std::clamp(result.diagnostics.level0.tracked_by_jump_rule, settings.min_tracked, settings.max_tracked));
  result.diagnostics.tracking.maps.resize(tracked_count);
  TrackingOptions tracking = settings.tracking;
  tracking.threads = 1;
  const TrackingPlan plan = plan_tracking(source, m, levels, tracking);
  std::atomic<int> done{0};
  parallel_for(tracked_count, threads, [&](int i, int) {
    result.diagnostics.tracking.maps[i] = track_map(source, target, plan, result.diagnostics.level0.maps[i], i, tracking, control);
    const int finished = ++done;
    control.report({"tracking", levels, total_levels, 0.1 + 0.6 * finished / tracked_count});
  });
  const std::vector<int> ranked = rank_tracked(result.diagnostics.tracking.maps, settings);
  result.diagnostics.tracking.chosen = ranked.front();
  clock.finish("tracking");

  DenseMap dense;
  if (settings.refine == RefineMethod::kNone) {
    // The C2F dense level from the chosen map only.
    control.report({"dense", total_levels, total_levels, 0.7});
    DenseOptions dense_options = settings.dense;
    dense_options.threads = threads;
    dense = compute_dense_map(source, target, result.diagnostics.tracking.maps[result.diagnostics.tracking.chosen].pairs, dense_options, control);
    clock.finish("dense");
  } else {
    control.report({"refine", total_levels, total_levels, 0.7});
    RefinedMatch refined = refine_and_choose(source, target, result.diagnostics.tracking.maps, ranked, settings, control);
    dense = std::move(refined.dense);
    result.diagnostics.refinement.screened = std::move(refined.screened);
    result.diagnostics.refinement.candidates = std::move(refined.candidates);
    result.diagnostics.refinement.chosen = refined.chosen;
    result.diagnostics.refinement.why = std::move(refined.why);
    result.timings.refine_steps = std::move(refined.timings);
    if (settings.outlier_repair)
      result.messages.notes.push_back("outlier repair: " + std::to_string(refined.repair.moved) + " of " +
                             std::to_string(refined.repair.flagged) + " flagged vertices placed again (" +
                             std::to_string(refined.repair.anchors) + " anchors)");
    if (settings.rigidity.mirror_repair && settings.rigidity.iterations > 0) {
      const MirrorRepair& chosen = refined.mirror_repair_chosen;
      const MirrorRepair& last = refined.mirror_repair;
      result.messages.notes.push_back(
          "mirror repair of the chosen map: " + std::to_string(chosen.segments) +
          " mirrored segments held at both ends unfolded before its spectral polish (" +
          std::to_string(chosen.reversed_vertices) + " vertices with reversed rings); after it " +
          std::to_string(last.segments) + " placed again" +
          (last.segments == 0 ? ""
           : last.kept        ? ", kept (lower rigidity energy)"
                              : ", not kept (higher rigidity energy)") +
          " (" + std::to_string(last.reversed_vertices) + " vertices with reversed rings)");
    }
    if (settings.refine_passes > 0)
      result.messages.notes.push_back("the chosen map refined again from itself " + std::to_string(settings.refine_passes) +
                             (settings.refine_passes == 1 ? " time" : " times"));
    if (settings.rigidity_final_iterations > 0) {
      char note[160];
      std::snprintf(note, sizeof note,
                    "final rigidity polish (%d iterations per weight): curvature disagreement %.4f -> %.4f, %s",
                    settings.rigidity_final_iterations, refined.final_polish.curvature_before,
                    refined.final_polish.curvature_after, refined.final_polish.kept ? "kept" : "not kept");
      result.messages.notes.push_back(note);
    }
    result.diagnostics.tracking.chosen = result.diagnostics.refinement.candidates[result.diagnostics.refinement.chosen].tracked_index;
    clock.finish("refine");
  }
  return dense;
}

// method = part or ravac: the part search or RAVAC (part_matching.h) and the complete
// pipeline both match the part, and the map whose smoothed curvature agrees better wins (mirrors, reversing most
// faces, lose first). They are right on different cuts (isocorr-bench-partial on faust_5k,
// scape, tosca_isometric_5k): the complete pipeline on parts that lost holes or a 30% ball,
// whose spectrum barely moves, the part search on half bodies. Curvature picked the right one
// on every cut where one was right; the boundary-aware distortion never picked the complete
// pipeline's map, as the part search's maps are fitted to that very measure.
DenseMap match_part_or_whole(const PreprocessedShape& source, const PreprocessedShape& target,
                             const MatchSettings& settings, MatchResult& result, const JobControl& control) {
  // The two share the match's progress: the part search its first half, the complete
  // pipeline the second (each reports fractions of its own run).
  auto share_of = [&control](double from, double span) {
    JobControl shared = control;
    if (control.on_progress)
      shared.on_progress = [&control, from, span](const Progress& p) {
        Progress scaled = p;
        scaled.fraction = from + span * p.fraction;
        control.report(scaled);
      };
    return shared;
  };
  // The notes name the method and its search: "part method" / "part search", "ravac method" / "RAVAC search".
  const bool ravac = settings.method == MatchMethod::kRavac;
  const std::string method_name = ravac ? "ravac method" : "part method";
  const std::string search_name = ravac ? "RAVAC search" : "part search";
  DenseMap part = match_part(source, target, settings, result, share_of(0, 0.5));
  // The Laplacian commutativity term assumes both spectra are one shape's: a part's
  // eigenvalues are not the whole's (its functional map to the whole is not near-diagonal),
  // so the complete pipeline runs without it here (FAUST 000 -> 004 with three holes: 0.059,
  // 7% of the points nearer their mirror image, with it).
  MatchSettings as_whole = settings;
  as_whole.zoomout.commutativity = 0;
  MatchResult whole_result;
  DenseMap whole;
  try {
    whole = match_complete(source, target, as_whole, whole_result, share_of(0.5, 0.5));
  } catch (const InputError& e) {
    result.messages.warnings.push_back(method_name + ": the " + search_name + "'s map kept; the complete pipeline failed: " +
                              e.what());
    return part;
  }
  const int threads = resolve_thread_count(settings.threads);
  std::vector<PartMapEvidence> evidence = measure_part_maps(source, target, {&part.forward, &whole.forward}, threads);
  // The complete pipeline's map refined as a part's (its ZoomOut fitted a square C, as if the
  // part were whole), kept if it then agrees better in curvature and keeps handedness.
  // Measured on the part benchmark's 36 development cuts: the same 31 right, Kim error of
  // the right ones 0.054 -> 0.048 (SCAPE 000 -> 001's 66% ball 0.035 -> 0.010, cat0 ->
  // cat3's 70% ball 0.050 -> 0.027), worse on 2 cuts by at most 0.001.
  if (finishes_part_maps(settings)) {
    DenseMap refined = refine_as_part_map(source, target, settings, evidence[1].scale, whole.forward, control);
    const PartMapEvidence refined_evidence = measure_part_maps(source, target, {&refined.forward}, threads)[0];
    const bool kept = refined_evidence.orientation >= settings.orientation_threshold &&
                      refined_evidence.curvature < evidence[1].curvature;
    result.messages.notes.push_back(method_name + ": the complete pipeline's map refined as a part's, curvature disagreement " +
                           std::to_string(evidence[1].curvature) + " -> " + std::to_string(refined_evidence.curvature) +
                           (kept ? ", kept" : ", not kept"));
    if (kept) {
      whole.forward = std::move(refined.forward);
      whole.forward_diso = std::move(refined.forward_diso);
      evidence[1] = refined_evidence;
    }
  }
  const PartMapEvidence& part_evidence = evidence[0];
  const PartMapEvidence& whole_evidence = evidence[1];
  // A mirrored map reverses most faces; among maps on the same side of that line the
  // smaller curvature disagreement wins.
  const bool part_upright = part_evidence.orientation >= settings.orientation_threshold;
  const bool whole_upright = whole_evidence.orientation >= settings.orientation_threshold;
  const bool whole_wins = whole_upright != part_upright ? whole_upright
                                                        : whole_evidence.curvature < part_evidence.curvature;
  auto describe = [](const char* name, const PartMapEvidence& e) {
    return std::string(name) + " curvature disagreement " + std::to_string(e.curvature) + ", orientation " +
           std::to_string(e.orientation) + ", distortion " + std::to_string(e.distortion) + ", scale " +
           std::to_string(e.scale);
  };
  const std::string why = method_name + ": the " + (whole_wins ? std::string("complete pipeline") : search_name) +
                          "'s map kept; " + describe(search_name.c_str(), part_evidence) + ", " +
                          describe("complete pipeline", whole_evidence);
  if (!whole_wins) {
    result.timings.stages.insert(result.timings.stages.end(), whole_result.timings.stages.begin(), whole_result.timings.stages.end());
    result.messages.notes.push_back(why);
    return part;
  }
  add_part_reverse_map(source, target, whole_evidence.scale, whole);
  whole_result.timings.stages.insert(whole_result.timings.stages.begin(), result.timings.stages.begin(), result.timings.stages.end());
  whole_result.messages.notes.insert(whole_result.messages.notes.begin(), result.messages.notes.begin(), result.messages.notes.end());
  whole_result.messages.warnings.insert(whole_result.messages.warnings.begin(), result.messages.warnings.begin(), result.messages.warnings.end());
  whole_result.messages.notes.push_back(why);
  whole_result.quality.part_scale = whole_evidence.scale;
  whole_result.diagnostics.part.candidates = std::move(result.diagnostics.part.candidates);
  for (PartCandidate& candidate : whole_result.diagnostics.part.candidates) candidate.kept = false;
  result = std::move(whole_result);
  return whole;
}

}  // namespace

MatchResult match_shapes(const PreprocessedShape& source, const PreprocessedShape& target,
                         const MatchSettings& settings, const JobControl& control) {
  MatchResult result;
  const DenseMap dense = settings.method != MatchMethod::kFull
                             ? match_part_or_whole(source, target, settings, result, control)
                             : match_complete(source, target, settings, result, control);

  // Back to the files' numbering; -1 (no counterpart) stays -1.
  const CleanMesh& sc = source.clean();
  const CleanMesh& tc = target.clean();
  MatchOutput& out = result.output;
  auto forward_in_files = [&](const std::vector<int>& clean_forward) {
    std::vector<int> in_files(sc.input_to_clean.size());
    for (size_t i = 0; i < in_files.size(); ++i) in_files[i] = tc.clean_to_input[clean_forward[sc.input_to_clean[i]]];
    return in_files;
  };
  out.forward = forward_in_files(dense.forward);
  out.forward_confidence.resize(sc.input_to_clean.size());
  for (size_t i = 0; i < sc.input_to_clean.size(); ++i) out.forward_confidence[i] = dense.forward_diso[sc.input_to_clean[i]];
  for (DenseCandidate& candidate : result.diagnostics.refinement.candidates) candidate.forward = forward_in_files(candidate.forward);
  for (PartCandidate& candidate : result.diagnostics.part.candidates) candidate.forward = forward_in_files(candidate.forward);
  out.reverse.resize(tc.input_to_clean.size());
  out.reverse_confidence.resize(tc.input_to_clean.size());
  for (size_t i = 0; i < tc.input_to_clean.size(); ++i) {
    const int c = tc.input_to_clean[i];
    out.reverse[i] = dense.reverse[c] < 0 ? -1 : sc.clean_to_input[dense.reverse[c]];
    out.reverse_confidence[i] = dense.reverse_diso[c];
  }
  if (result.diagnostics.refinement.candidates.empty()) {
    double sum = 0, worst = 0;
    for (float d : dense.forward_diso) sum += d, worst = std::max(worst, static_cast<double>(d));
    result.quality.diso = sum / std::max<size_t>(1, dense.forward_diso.size());
    result.quality.diso_max = worst;
  } else {  // refined: the winner's distortion between coarse samples, measured exactly
    result.quality.diso = result.diagnostics.refinement.candidates[result.diagnostics.refinement.chosen].evidence.distortion;
    result.quality.diso_max = result.diagnostics.refinement.candidates[result.diagnostics.refinement.chosen].evidence.distortion_max;
  }
  // Refined: measured already while choosing.
  result.quality.orientation = result.diagnostics.refinement.candidates.empty()
                                 ? dense_orientation_agreement(source.mesh(), source.normals(), target.mesh(),
                                                             target.normals(), dense.forward)
                                 : result.diagnostics.refinement.candidates[result.diagnostics.refinement.chosen].evidence.orientation;
  if (settings.method != MatchMethod::kFull) {
    result.quality.target_matched_share = matched_area_share(vertex_areas(target.mesh()), dense.reverse);
    // Kappa in the files' units: each mesh was normalised by its own power of two.
    result.quality.part_scale = length_ratio_in_files(result.quality.part_scale, sc.normalisation, tc.normalisation);
    for (PartCandidate& candidate : result.diagnostics.part.candidates)
      candidate.scale = length_ratio_in_files(candidate.scale, sc.normalisation, tc.normalisation);
  }
  for (const auto& repair : sc.repairs) result.messages.warnings.push_back("source: " + repair);
  for (const auto& repair : tc.repairs) result.messages.warnings.push_back("target: " + repair);
  control.report({"done", 1, 1, 1.0});
  return result;
}

}  // namespace isocorr
