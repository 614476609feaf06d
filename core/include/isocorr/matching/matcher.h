// Matching two complete preprocessed shapes: level-0 search -> flip tracking -> choice ->
// the C2F dense level or the refinement. pipeline/match_shapes.h chooses between this and
// the part methods; pipeline/run_match.h adds the preprocessing, and most callers want that.
#pragma once

#include <string>
#include <vector>

#include "isocorr/matching/dense_map.h"
#include "isocorr/matching/flip_tracking.h"
#include "isocorr/matching/level0_search.h"
#include "isocorr/output/match_result.h"
#include "isocorr/settings/match_settings.h"
#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

// Normalised geodesic distances between the first `count` samples of a shape, symmetrised
// (fast marching is not exactly symmetric): the level-0 search's input.
Eigen::MatrixXd sample_distances(const PreprocessedShape& shape, int count);
// The same between the listed samples, in their order.
Eigen::MatrixXd sample_distances(const PreprocessedShape& shape, const std::vector<int>& samples);

// The choice among tracked maps: those whose orientation agreement is within
// settings.orientation_margin of the best compete on D_iso - weight * orientation; returns
// all indices, best first.
std::vector<int> rank_tracked(const std::vector<TrackedMap>& tracked, const MatchSettings& settings);

// The dense map (clean numbering) of two complete shapes. Fills `result`'s diagnostics,
// stage timings and notes. `settings` must have passed validate(). Reports progress as
// fractions of this match alone.
DenseMap match_whole(const PreprocessedShape& source, const PreprocessedShape& target, const MatchSettings& settings,
                     MatchResult& result, const JobControl& control);

}  // namespace isocorr
