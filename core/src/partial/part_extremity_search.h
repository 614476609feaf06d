// Steps 1 and 2 of the part search (part_matching.h): the part's extremities matched to
// target samples over all injective maps, ranked by scale-free distortion, then screened by
// growing the first levels' samples from each.
#pragma once

#include <vector>

#include "isocorr/output/match_result.h"
#include "isocorr/settings/match_settings.h"
#include "isocorr/util/progress.h"
#include "part_geometry.h"

namespace isocorr {

// The candidates, with kappa from their screened maps; `level0` gets every extremity map
// ranked, `ranks` each candidate's rank among them.
std::vector<ExtremityMap> part_search_candidates(const PartGeometry& part, const MatchSettings& settings, int threads,
                                                 Level0Diagnostics& level0, std::vector<int>& ranks,
                                                 const JobControl& control);

}  // namespace isocorr
