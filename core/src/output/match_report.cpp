#include "isocorr/output/match_report.h"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "isocorr/settings/settings_json.h"
#include "isocorr/version.h"

namespace isocorr {

std::string match_report_json(const MatchResult& result, const MatchSettings& settings) {
  using nlohmann::json;
  json report;
  report["version"] = kVersion;
  report["settings"] = settings_to_json(settings);
  json timings = json::object();
  double total = 0;
  for (const auto& t : result.timings.stages) timings[t.stage] = t.seconds, total += t.seconds;
  timings["total"] = total;
  report["timings_seconds"] = timings;
  // The refine stage's steps, apart: they are part of its time, not added to the total.
  if (!result.timings.refine_steps.empty()) {
    json steps = json::object();
    for (const auto& t : result.timings.refine_steps) steps[t.stage] = t.seconds;
    report["refine_steps_seconds"] = steps;
  }

  const Level0Diagnostics& level0_maps = result.diagnostics.level0;
  const TrackingDiagnostics& tracking = result.diagnostics.tracking;
  const RefinementDiagnostics& refinement = result.diagnostics.refinement;
  json level0 = json::array();
  const size_t shown = std::min<size_t>(level0_maps.maps.size(), 20);
  for (size_t i = 0; i < shown; ++i)
    level0.push_back({{"rank", i}, {"diso", level0_maps.maps[i].diso}, {"target_of", level0_maps.maps[i].target_of}});
  report["level0"] = {{"maps_under_threshold", level0_maps.maps.size()}, {"best", level0},
                      {"tracked_by_jump_rule", level0_maps.tracked_by_jump_rule}};
  json tracked = json::array();
  for (const auto& t : tracking.maps)
    tracked.push_back({{"level0_rank", t.level0_rank}, {"level0_diso", t.level0_diso},
                       {"pairs", t.pairs.size()}, {"diso", t.diso}, {"orientation", t.orientation}});
  report["tracked"] = tracked;
  report["chosen"] = tracking.chosen;
  if (!refinement.candidates.empty()) {
    json refined = json::array();
    for (const auto& c : refinement.candidates)
      refined.push_back({{"tracked", c.tracked_index},
                         {"level0_rank", tracking.maps[c.tracked_index].level0_rank},
                         {"orientation", c.evidence.orientation},
                         {"neighbourhood_orientation", c.evidence.neighbourhood_orientation},
                         {"signature_disagreement", c.evidence.signature_disagreement},
                         {"curvature_disagreement", c.evidence.curvature_disagreement},
                         {"distortion", c.evidence.distortion},
                         {"distortion_max", c.evidence.distortion_max},
                         {"round_trip", c.evidence.round_trip},
                         {"score", c.score},
                         {"reverse_score", c.reverse_score},
                         {"mirrored", c.mirrored},
                         {"finished", c.finished}});
    json screened = json::array();
    for (const auto& s : refinement.screened) {
      const bool went_on = std::any_of(refinement.candidates.begin(), refinement.candidates.end(),
                                       [&](const DenseCandidate& c) { return c.tracked_index == s.tracked_index; });
      screened.push_back({{"tracked", s.tracked_index},
                          {"orientation", s.orientation},
                          {"curvature_disagreement", s.curvature},
                          {"refined", went_on}});
    }
    report["refined"] = {{"screened", screened},
                         {"candidates", refined},
                         {"chosen", refinement.chosen},
                         {"why", refinement.why}};
  }
  const LandmarkDiagnostics& landmarks = result.diagnostics.landmarks;
  if (landmarks.count > 0)
    report["landmarks"] = {{"count", landmarks.count},
                           {"level0_maps_dropped", landmarks.level0_dropped},
                           {"level0_none_agreed", landmarks.level0_none_agreed},
                           {"chosen_map_errors", landmarks.chosen_errors},
                           {"chosen_map_honours_them", landmarks.honoured}};
  report["final"] = {{"diso", result.quality.diso}, {"diso_max", result.quality.diso_max},
                     {"orientation", result.quality.orientation},
                     {"torn_share", result.quality.torn_share},
                     {"source_vertices", result.output.forward.size()},
                     {"target_vertices", result.output.reverse.size()}};
  if (settings.method != MatchMethod::kFull) {
    long matched = 0;
    for (int s : result.output.reverse) matched += s >= 0;
    // The reverse map has -1 where the target has no counterpart in the part.
    json candidates = json::array();
    for (const PartCandidate& c : result.diagnostics.part.candidates)
      candidates.push_back({{"orientation", c.orientation},
                            {"curvature_disagreement", c.curvature},
                            {"covered_share", c.covered},
                            {"scale", c.scale},
                            {"distortion", c.distortion},
                            {"extremity_distortion", c.level0_distortion},
                            {"finalist", c.finalist}});
    report["part"] = {{"scale", result.quality.part_scale},
                      {"target_matched_share", result.quality.target_matched_share},
                      {"target_vertices_matched", matched},
                      {"search_candidates", candidates}};
  }
  report["verdict"] = {{"status", result.verdict.status()}, {"reasons", result.verdict.reasons}};
  report["warnings"] = result.messages.warnings;
  report["notes"] = result.messages.notes;
  return report.dump(2);
}

std::string report_with_inputs(const std::string& report_json, const ReportInput& source, const ReportInput& target) {
  nlohmann::json report = nlohmann::json::parse(report_json);
  report["inputs"] = {{"source", {{"file", source.file}, {"sha256", source.sha256}}},
                      {"target", {{"file", target.file}, {"sha256", target.sha256}}}};
  return report.dump(2);
}

}  // namespace isocorr
