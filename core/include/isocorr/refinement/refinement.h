// The refinement stage after tracking: the best few distinct tracked maps are refined into
// dense maps (ZoomOut from their sample pairs, then outlier repair and the rigidity
// polish), measured by dense evidence, and the best refined map is the result.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "isocorr/matching/dense_map.h"
#include "isocorr/refinement/candidate_screening.h"
#include "isocorr/refinement/dense_choice.h"
#include "isocorr/refinement/final_polish.h"
#include "isocorr/refinement/outlier_repair.h"
#include "isocorr/refinement/rigidity_polish.h"
#include "isocorr/settings/match_settings.h"
#include "isocorr/transfer/landmarks.h"
#include "isocorr/util/stage_clock.h"

namespace isocorr {

struct RefinedMatch {
  DenseMap dense;  // the winner, clean numbering; confidence is the last stage's residual
                   // (rigidity_polish.h, or the spectral residual when it is off)
  std::vector<ScreenEvidence> screened;  // every screened start, in the tracked ranking
  std::vector<DenseCandidate> candidates;
  int chosen = 0;  // index into candidates
  std::string why;
  OutlierRepair repair;  // what the outlier repair of the winner did (settings.outlier_repair)
  // What the mirror repair did to the winner once chosen, and in its last rigidity polish
  // (settings.rigidity.mirror_repair).
  MirrorRepair mirror_repair_chosen, mirror_repair;
  Eigen::MatrixXf functional_map;  // the winner's last C (SpectralMap::c)
  FinalPolishOutcome final_polish;  // settings.rigidity_final_iterations (after settings.refine_passes)
  // Wall-clock time of each stage, named as refine_and_choose runs them: screen, refine,
  // drop_duplicates, preselect, finish, choose, unfold_mirrors, spectral_polish,
  // curvature_polish, finish_with_mirror_repair, refine_again, final_polish.
  std::vector<StageTiming> timings;
};

// `ranked`: tracked-map indices, best first by the sparse choice rule. The first
// `settings.screen_candidates` of them whose sample images differ (a tracked map that ends
// where a better-ranked one did is skipped) are screened on the samples, and
// `settings.refine_candidates` of them are picked from the ranking and the screen in turn
// (candidate_screening.h) and refined fully (a refined map that ends where an earlier one
// did is dropped: same_dense_map in the source). Of those that pass the mirror test, up to
// three whose raw curvature disagreement is within 15% of the best raw one's are finished
// (outlier repair, rigidity polish), and the finished ones compete (dense_choice.h); only
// when none passes the mirror test do unfinished ones, and a winner among them is
// finished then. `landmarks` join every start's pairs, and when some refined map honours
// them only those are finished and compete (dense_choice.h); the caller pins them.
RefinedMatch refine_and_choose(const PreprocessedShape& source, const PreprocessedShape& target,
                               const std::vector<TrackedMap>& tracked, const std::vector<int>& ranked,
                               const MatchSettings& settings, const JobControl& control,
                               const LandmarkGeometry& landmarks = LandmarkGeometry());

// One map refined as the chosen candidate is, from (source vertex, target vertex) pairs in
// the shapes' clean numbering instead of a tracked map: ZoomOut from the pairs up to
// settings.zoomout.k_end, then the outlier repair, the rigidity polish and the optional
// spectral polish (zoomout_polish_k_end) as `settings` say.
// Started from the ground truth, its error is the refinement's own, whatever the start
// (isocorr-bench --from-truth). At least settings.zoomout.k_start pairs.
SpectralMap refine_from_pairs(const PreprocessedShape& source, const PreprocessedShape& target,
                              const std::vector<std::pair<int, int>>& pairs, const MatchSettings& settings,
                              const JobControl& control = {});

// A refined map refined once more, from its own images of the source's spectral samples:
// refine_from_pairs with ZoomOut started at half of settings.zoomout.k_end instead of
// k_start. A tracked map is too coarse to start that high (it ends mirrored), so the first
// refinement starts low, and its low-frequency stage leaves the truth by about a percent of
// the diameter on scans in stretched poses; a second refinement from the first one's right
// map can skip that stage. settings.refine_passes of these follow the chosen map's polish.
SpectralMap refine_again(const PreprocessedShape& source, const PreprocessedShape& target, const SpectralMap& map,
                         const MatchSettings& settings, const JobControl& control = {});

}  // namespace isocorr
