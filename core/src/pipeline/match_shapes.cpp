#include "isocorr/pipeline/match_shapes.h"

#include <algorithm>
#include <vector>

#include "isocorr/diagnosis/map_tearing.h"
#include "isocorr/diagnosis/verdict.h"
#include "isocorr/matching/matcher.h"
#include "isocorr/matching/orientation.h"
#include "isocorr/mesh/coordinate_normalisation.h"
#include "isocorr/partial/part_matching.h"
#include "isocorr/partial/part_or_whole.h"
#include "isocorr/transfer/landmarks.h"
#include "isocorr/transfer/precise_map.h"
#include "isocorr/util/stage_clock.h"

namespace isocorr {

namespace {

// The dense map of clean vertices, and the candidates' maps, in the input files' numbering;
// -1 (no counterpart) stays -1.
void to_file_numbering(const DenseMap& dense, const CleanMesh& source, const CleanMesh& target, MatchResult& result) {
  auto forward_in_files = [&](const std::vector<int>& clean_forward) {
    std::vector<int> in_files(source.input_to_clean.size());
    for (size_t i = 0; i < in_files.size(); ++i)
      in_files[i] = target.clean_to_input[clean_forward[source.input_to_clean[i]]];
    return in_files;
  };
  MatchOutput& out = result.output;
  out.forward = forward_in_files(dense.forward);
  out.forward_confidence.resize(source.input_to_clean.size());
  for (size_t i = 0; i < source.input_to_clean.size(); ++i)
    out.forward_confidence[i] = dense.forward_diso[source.input_to_clean[i]];
  for (DenseCandidate& candidate : result.diagnostics.refinement.candidates)
    candidate.forward = forward_in_files(candidate.forward);
  for (PartCandidate& candidate : result.diagnostics.part.candidates)
    candidate.forward = forward_in_files(candidate.forward);
  out.reverse.resize(target.input_to_clean.size());
  out.reverse_confidence.resize(target.input_to_clean.size());
  for (size_t i = 0; i < target.input_to_clean.size(); ++i) {
    const int c = target.input_to_clean[i];
    out.reverse[i] = dense.reverse[c] < 0 ? -1 : source.clean_to_input[dense.reverse[c]];
    out.reverse_confidence[i] = dense.reverse_diso[c];
  }
}

// D_iso, d_iso-dagger and orientation of the returned map. A refined map's were measured
// while choosing (D_iso as the winner's distortion between coarse samples, exactly); the
// C2F map's come from its anchors' residuals.
void measure_quality(const PreprocessedShape& source, const PreprocessedShape& target, const DenseMap& dense,
                     MatchMethod method, MatchResult& result) {
  const RefinementDiagnostics& refinement = result.diagnostics.refinement;
  MatchQuality& quality = result.quality;
  if (method == MatchMethod::kFull) quality.torn_share = measure_map_tearing(source, target, dense.forward).torn_share();
  if (!refinement.candidates.empty()) {
    const DenseEvidence& winner = refinement.candidates[refinement.chosen].evidence;
    quality.diso = winner.distortion;
    quality.diso_max = winner.distortion_max;
    quality.orientation = winner.orientation;
    return;
  }
  double sum = 0, worst = 0;
  for (float d : dense.forward_diso) sum += d, worst = std::max(worst, static_cast<double>(d));
  quality.diso = sum / std::max<size_t>(1, dense.forward_diso.size());
  quality.diso_max = worst;
  quality.orientation =
      dense_orientation_agreement(source.mesh(), source.normals(), target.mesh(), target.normals(), dense.forward);
}

}  // namespace

MatchResult match_shapes(const PreprocessedShape& source, const PreprocessedShape& target,
                         const MatchSettings& settings, const JobControl& control) {
  // The landmarks' range needs the meshes: the files' vertex counts.
  validate_landmarks(settings.landmarks, static_cast<int>(source.clean().input_to_clean.size()),
                     static_cast<int>(target.clean().input_to_clean.size()));
  MatchResult result;
  const DenseMap dense = settings.method != MatchMethod::kFull
                             ? match_part_or_whole(source, target, settings, result, control)
                             : match_whole(source, target, settings, result, control);
  StageClock clock(result.timings.stages);
  measure_quality(source, target, dense, settings.method, result);
  result.verdict = diagnose(source, target, result);
  clock.finish("diagnose");
  const CleanMesh& sc = source.clean();
  const CleanMesh& tc = target.clean();
  to_file_numbering(dense, sc, tc, result);
  result.output.forward_precise = precise_map_in_files(sc, tc, dense.forward, control.threads);
  result.output.reverse_precise = precise_map_in_files(tc, sc, dense.reverse, control.threads);
  clock.finish("precise_maps");
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
