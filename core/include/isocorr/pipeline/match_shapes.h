// One match of two preprocessed shapes by the settings' method: the complete pipeline
// (matching/matcher.h) or a part method (partial/part_or_whole.h), its map returned in the
// input files' numbering with its final measures. run_match.h adds the preprocessing.
#pragma once

#include "isocorr/output/match_result.h"
#include "isocorr/settings/match_settings.h"
#include "isocorr/shape/preprocessed_shape.h"
#include "isocorr/util/progress.h"

namespace isocorr {

// Matches two preprocessed shapes. `settings` must have passed validate() (run_match
// does that once); the landmarks' range against the meshes is checked here (InputError
// "landmarks[i]: ..."). Deterministic for given inputs and settings. Reports progress as
// fractions of the match alone.
MatchResult match_shapes(const PreprocessedShape& source, const PreprocessedShape& target,
                         const MatchSettings& settings, const JobControl& control = {});

}  // namespace isocorr
