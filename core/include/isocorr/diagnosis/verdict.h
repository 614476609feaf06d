// The verdict on a finished match: "ok", or "suspect" with the reasons, from evidence a
// right map shows and a wrong one may not. The checks (docs/algorithm.md, "The verdict"):
//  - a close competitor: another refined candidate that keeps handedness, lies far from the
//    chosen map, and scored nearly as well by the dense choice: the choice was a near tie
//    between two different maps, and a mirrored or turned body often wins such ties;
//  - reversed handedness: the map reverses the handedness of most faces (only possible when
//    every candidate did, and the choice fell back to the best of them);
//  - tearing: more neighbouring points of the source land far apart than on right maps
//    (map_tearing.h): the border of a region mapped to the wrong place;
//  - landmarks not honoured: the chosen map sent a landmark beyond kLandmarkTolerance before
//    it was pinned.
// The thresholds were set on the development pairs with their ground truth
// (docs/benchmarks.md): every wrong map flagged and few right ones.
#pragma once

#include <vector>

#include "isocorr/output/match_result.h"
#include "isocorr/refinement/dense_choice.h"
#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

// A candidate whose score is within this share of the winner's is a close competitor
// (score / winner's score - 1).
inline constexpr double kCloseCompetitorMargin = 0.05;
// ... when it lies at least this far from the chosen map: the mean over the source's
// spectral samples of the geodesic distance between the two images, / the target's
// diameter (a lower bound, from the target's sample fields). Two refinements of one map
// differ by up to 0.03; a swapped limb moves the mean 0.05-0.1, a turned body 0.3-0.5.
inline constexpr double kDistinctMapSeparation = 0.05;

// How far apart two maps (clean source vertex -> clean target vertex) send the source's
// spectral samples on the target, on average, / the target's diameter: for each sample the
// largest difference of the target's sample fields at the two images (each field is
// 1-Lipschitz, so this never exceeds the geodesic distance).
double map_separation(const PreprocessedShape& source, const PreprocessedShape& target, const std::vector<int>& a,
                      const std::vector<int>& b);

// The candidates other than `chosen` that keep handedness, honour the landmarks, scored
// within kCloseCompetitorMargin of it and lie at least kDistinctMapSeparation from it
// (clean numbering), closest in score first.
std::vector<int> close_competitors(const PreprocessedShape& source, const PreprocessedShape& target,
                                   const std::vector<DenseCandidate>& candidates, int chosen);

// The verdict on `result` (candidates still in clean numbering: called before the maps are
// put in the files' numbering); the tearing check reads result.quality.torn_share.
MatchVerdict diagnose(const PreprocessedShape& source, const PreprocessedShape& target, const MatchResult& result);

}  // namespace isocorr
