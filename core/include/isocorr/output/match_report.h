// The JSON report of a match: settings, timings per stage, level-0 candidates, tracked
// maps and the chosen one, final distortion, repairs.
#pragma once

#include <string>

#include "isocorr/output/match_result.h"
#include "isocorr/settings/match_settings.h"

namespace isocorr {

// The report of `result`, with the version of isocorr that made it.
std::string match_report_json(const MatchResult& result, const MatchSettings& settings);

// A mesh a report names: its file (or stored name) and the SHA-256 of its bytes.
struct ReportInput {
  std::string file, sha256;
};

// `report_json` with an "inputs" object naming the source and target meshes, so that a result
// can be traced to what made it.
std::string report_with_inputs(const std::string& report_json, const ReportInput& source, const ReportInput& target);

}  // namespace isocorr
