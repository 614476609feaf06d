// Step 3 of the part search (part_matching.h): an extremity map grown coarse to fine to a
// map of the part's samples, each sample against every pair matched before it.
#pragma once

#include <vector>

#include "isocorr/matching/flip_tracking.h"
#include "isocorr/util/progress.h"
#include "part_geometry.h"

namespace isocorr {

// Trimmed mean of per-anchor mismatches: the largest share (a fifth) is left out, so a few
// misplaced pairs do not decide a cost.
float trimmed_mean(std::vector<float>& terms);

// Source samples of schedule steps up to `last_step` matched to target samples from `start`
// (its `rank` among the extremity maps); `grown_scale` gets kappa re-estimated from the
// grown map's exact distances.
TrackedMap grow_sample_map(const PartGeometry& part, const ExtremityMap& start, int rank, int last_step,
                           double& grown_scale, const JobControl& control);

}  // namespace isocorr
