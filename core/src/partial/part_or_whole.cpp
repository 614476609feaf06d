#include "isocorr/partial/part_or_whole.h"

#include <cmath>
#include <string>
#include <vector>

#include "isocorr/matching/matcher.h"
#include "isocorr/partial/part_matching.h"
#include "isocorr/transfer/landmarks.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

template <class T>
void append(std::vector<T>& to, const std::vector<T>& more) {
  to.insert(to.end(), more.begin(), more.end());
}

// What the part-or-whole choice minimises: choice_score (dense_choice.h) of the evidence.
double part_choice_score(const PartMapEvidence& evidence) {
  return evidence.curvature * std::cbrt(evidence.distortion);
}

}  // namespace

// method = part or ravac: the part search or RAVAC (part_matching.h) and the complete
// pipeline both match the part, and the map with the lesser curvature disagreement times
// the cube root of distortion wins, the score of the complete pipeline's own dense choice
// (landmarks first, then mirrors, reversing most faces, lose). They are right on different
// cuts (isocorr-bench-partial on faust_5k, scape, tosca_isometric_5k): the complete pipeline
// on parts that lost holes or a 30% ball, whose spectrum barely moves, the part search on
// half bodies. Distortion alone never picked the complete pipeline's map, as the part
// search's maps are fitted to that very measure; curvature alone picked a turned body on
// FAUST 002 -> 007's 70% ball (10% less curvature disagreement, twice the distortion). With
// the cube root: 32 -> 33 of the 36 cuts right, SCAPE 000 -> 001's 66% ball 0.019 -> 0.0075,
// no cut worse by more than 0.0001.
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
  const LandmarkGeometry landmarks(source, target, settings.landmarks);
  // The Laplacian commutativity term assumes both spectra are one shape's: a part's
  // eigenvalues are not the whole's (its functional map to the whole is not near-diagonal),
  // so the complete pipeline runs without it here (FAUST 000 -> 004 with three holes: 0.059,
  // 7% of the points nearer their mirror image, with it).
  MatchSettings as_whole = settings;
  as_whole.zoomout.commutativity = 0;
  MatchResult whole_result;
  DenseMap whole;
  try {
    whole = match_whole(source, target, as_whole, whole_result, share_of(0.5, 0.5));
  } catch (const InputError& e) {
    result.messages.warnings.push_back(method_name + ": the " + search_name +
                                       "'s map kept; the complete pipeline failed: " + e.what());
    hold_landmarks(landmarks, part, result);
    return part;
  }
  const int threads = resolve_thread_count(control.threads);
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
    result.messages.notes.push_back(method_name +
                                    ": the complete pipeline's map refined as a part's, curvature disagreement " +
                                    std::to_string(evidence[1].curvature) + " -> " +
                                    std::to_string(refined_evidence.curvature) + (kept ? ", kept" : ", not kept"));
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
  // Landmarks come first: a map that sends one beyond kLandmarkTolerance loses to one that
  // does not (the complete pipeline's was measured before it pinned them).
  const bool part_holds = landmarks.largest_error(part.forward) <= kLandmarkTolerance;
  const bool whole_holds = whole_result.diagnostics.landmarks.honoured;
  const bool whole_wins = part_holds != whole_holds       ? whole_holds
                          : whole_upright != part_upright ? whole_upright
                                                          : part_choice_score(whole_evidence) < part_choice_score(part_evidence);
  auto describe = [](const char* name, const PartMapEvidence& e) {
    return std::string(name) + " curvature disagreement " + std::to_string(e.curvature) + ", orientation " +
           std::to_string(e.orientation) + ", distortion " + std::to_string(e.distortion) + ", scale " +
           std::to_string(e.scale);
  };
  const std::string why = method_name + ": the " + (whole_wins ? std::string("complete pipeline") : search_name) +
                          "'s map kept; " + describe(search_name.c_str(), part_evidence) + ", " +
                          describe("complete pipeline", whole_evidence);
  if (!whole_wins) {
    append(result.timings.stages, whole_result.timings.stages);
    result.messages.notes.push_back(why);
    hold_landmarks(landmarks, part, result);
    return part;
  }
  add_part_reverse_map(source, target, whole_evidence.scale, whole);
  pin_landmarks(landmarks, whole.forward, whole.reverse);  // the refinement as a part's may have moved them
  // The part search ran first: its timings and remarks come before the complete pipeline's.
  append(result.timings.stages, whole_result.timings.stages);
  append(result.messages.notes, whole_result.messages.notes);
  append(result.messages.warnings, whole_result.messages.warnings);
  whole_result.timings.stages = std::move(result.timings.stages);
  whole_result.messages = std::move(result.messages);
  whole_result.messages.notes.push_back(why);
  whole_result.quality.part_scale = whole_evidence.scale;
  whole_result.diagnostics.part.candidates = std::move(result.diagnostics.part.candidates);
  for (PartCandidate& candidate : whole_result.diagnostics.part.candidates) candidate.kept = false;
  result = std::move(whole_result);
  return whole;
}

}  // namespace isocorr
