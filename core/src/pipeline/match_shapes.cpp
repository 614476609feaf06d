#include "isocorr/pipeline/match_shapes.h"

#include <algorithm>
#include <vector>

#include "isocorr/matching/matcher.h"
#include "isocorr/matching/orientation.h"
#include "isocorr/mesh/coordinate_normalisation.h"
#include "isocorr/partial/part_matching.h"
#include "isocorr/partial/part_or_whole.h"

namespace isocorr {

MatchResult match_shapes(const PreprocessedShape& source, const PreprocessedShape& target,
                         const MatchSettings& settings, const JobControl& control) {
  MatchResult result;
  const DenseMap dense = settings.method != MatchMethod::kFull
                             ? match_part_or_whole(source, target, settings, result, control)
                             : match_whole(source, target, settings, result, control);

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
