// An optional longer rigidity polish of the chosen map, kept only where it agrees better.
//
// The rigidity polish (rigidity_polish.h) removes a refined map's slide slowly: its long
// wavelengths are soft under a local rigidity energy, and more iterations keep moving the
// map. Whether they move it towards the truth depends on the pair. On real scans in
// stretched poses they do (SCAPE's first 10 pairs, 130 more iterations per fit weight:
// D_grd 0.0091 -> 0.0084, mesh000 -> mesh007 0.032 -> 0.028); on TOSCA's synthetic poses
// they mostly drift (TOSCA 5k's 17 flip-free pairs, 150 per weight instead of 20: 0.0154 ->
// 0.0162). The smoothed curvature disagreement (dense_choice.h), which no stage is fitted
// to, tells the two apart: it rose on 10 of the 11 TOSCA 5k pairs whose error rose (the
// eleventh by 0.0001) and fell on 8 of SCAPE's 10. Kept only where it fell, at 130:
// SCAPE's 10 0.0091 -> 0.0084, TOSCA 5k 0.0154 -> 0.0152, FAUST 5k's first 20 0.0113 ->
// 0.0111.
#pragma once

#include "isocorr/refinement/zoomout.h"
#include "isocorr/shape/preprocessed_shape.h"
#include "isocorr/util/progress.h"

namespace isocorr {

struct FinalPolishOutcome {
  bool kept = false;
  double curvature_before = 0, curvature_after = 0;
};

// Polishes a copy of `map` (forward and, when present, reverse) by `iterations` more
// as-rigid-as-possible iterations per fit weight on `threads` workers (0 = all cores), and
// replaces `map` by it only when its curvature disagreement is lower. Deterministic.
FinalPolishOutcome extend_rigidity_polish(const PreprocessedShape& source, const PreprocessedShape& target,
                                          int iterations, int threads, SpectralMap& map,
                                          const JobControl& control = {});

}  // namespace isocorr
