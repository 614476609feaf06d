// The part methods' last choice: the part search's (or RAVAC's) map against the complete
// pipeline's, both made for the same part (docs/partial.md).
#pragma once

#include "isocorr/matching/dense_map.h"
#include "isocorr/output/match_result.h"
#include "isocorr/settings/match_settings.h"
#include "isocorr/shape/preprocessed_shape.h"
#include "isocorr/util/progress.h"

namespace isocorr {

// method = part or ravac: the source is a part of the target. Runs the part search (or
// RAVAC) and the complete pipeline, and returns the dense map (clean numbering) whose
// smoothed curvature agrees better; `result` holds the winner's diagnostics and notes.
DenseMap match_part_or_whole(const PreprocessedShape& source, const PreprocessedShape& target,
                             const MatchSettings& settings, MatchResult& result, const JobControl& control);

}  // namespace isocorr
