#include "isocorr/output/match_result.h"

namespace isocorr {

MatchSummary MatchResult::summary() const {
  MatchSummary s;
  s.source_vertices = static_cast<int>(output.forward.size());
  s.target_vertices = static_cast<int>(output.reverse.size());
  s.diso = quality.diso;
  s.diso_max = quality.diso_max;
  s.dense_orientation = quality.orientation;
  const TrackingDiagnostics& tracking = diagnostics.tracking;
  s.level0_maps = static_cast<int>(diagnostics.level0.maps.size());
  s.tracked_maps = static_cast<int>(tracking.maps.size());
  s.chosen_level0_rank = tracking.maps.empty() ? 0 : tracking.maps[tracking.chosen].level0_rank;
  s.timings = timings.stages;
  // The API has one list: warnings first.
  s.notes = messages.warnings;
  s.notes.insert(s.notes.end(), messages.notes.begin(), messages.notes.end());
  s.verdict = verdict.status();
  s.verdict_reasons = verdict.reasons;
  return s;
}

}  // namespace isocorr
