// The JSON report of a match: settings, timings per stage, level-0 candidates, tracked
// maps and the chosen one, final distortion, repairs.
#pragma once

#include <string>

#include "isocorr/matching/matcher.h"

namespace isocorr {

std::string match_report_json(const MatchResult& result, const MatchSettings& settings);

}  // namespace isocorr
