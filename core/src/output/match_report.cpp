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
  for (const auto& t : result.timings) timings[t.stage] = t.seconds, total += t.seconds;
  timings["total"] = total;
  report["timings_seconds"] = timings;
  // The refine stage's steps, apart: they are part of its time, not added to the total.
  if (!result.refine_timings.empty()) {
    json steps = json::object();
    for (const auto& t : result.refine_timings) steps[t.stage] = t.seconds;
    report["refine_steps_seconds"] = steps;
  }

  json level0 = json::array();
  const size_t shown = std::min<size_t>(result.level0.size(), 20);
  for (size_t i = 0; i < shown; ++i)
    level0.push_back({{"rank", i}, {"diso", result.level0[i].diso}, {"target_of", result.level0[i].target_of}});
  report["level0"] = {{"maps_under_threshold", result.level0.size()}, {"best", level0},
                      {"tracked_by_jump_rule", result.tracked_by_jump_rule}};
  json tracked = json::array();
  for (const auto& t : result.tracked)
    tracked.push_back({{"level0_rank", t.level0_rank}, {"level0_diso", t.level0_diso},
                       {"pairs", t.pairs.size()}, {"diso", t.diso}, {"orientation", t.orientation}});
  report["tracked"] = tracked;
  report["chosen"] = result.chosen;
  if (!result.refined.empty()) {
    json refined = json::array();
    for (const auto& c : result.refined)
      refined.push_back({{"tracked", c.tracked_index},
                         {"level0_rank", result.tracked[c.tracked_index].level0_rank},
                         {"orientation", c.evidence.orientation},
                         {"neighbourhood_orientation", c.evidence.neighbourhood_orientation},
                         {"signature_disagreement", c.evidence.signature_disagreement},
                         {"curvature_disagreement", c.evidence.curvature_disagreement},
                         {"distortion", c.evidence.distortion},
                         {"distortion_max", c.evidence.distortion_max},
                         {"round_trip", c.evidence.round_trip},
                         {"score", c.score},
                         {"mirrored", c.mirrored},
                         {"finished", c.finished}});
    json screened = json::array();
    for (const auto& s : result.screened) {
      const bool went_on = std::any_of(result.refined.begin(), result.refined.end(),
                                       [&](const DenseCandidate& c) { return c.tracked_index == s.tracked_index; });
      screened.push_back({{"tracked", s.tracked_index},
                          {"orientation", s.orientation},
                          {"curvature_disagreement", s.curvature},
                          {"refined", went_on}});
    }
    report["refined"] = {{"screened", screened},
                         {"candidates", refined},
                         {"chosen", result.refined_chosen},
                         {"why", result.refined_why}};
  }
  report["final"] = {{"diso", result.diso}, {"diso_max", result.diso_max},
                     {"orientation", result.dense_orientation},
                     {"source_vertices", result.output.forward.size()},
                     {"target_vertices", result.output.reverse.size()}};
  if (settings.method != MatchMethod::kFull) {
    long matched = 0;
    for (int s : result.output.reverse) matched += s >= 0;
    // The reverse map has -1 where the target has no counterpart in the part.
    json candidates = json::array();
    for (const PartCandidate& c : result.part_candidates)
      candidates.push_back({{"orientation", c.orientation},
                            {"curvature_disagreement", c.curvature},
                            {"covered_share", c.covered},
                            {"scale", c.scale},
                            {"distortion", c.distortion},
                            {"extremity_distortion", c.level0_distortion},
                            {"finalist", c.finalist}});
    report["part"] = {{"scale", result.part_scale},
                      {"target_matched_share", result.target_matched_share},
                      {"target_vertices_matched", matched},
                      {"search_candidates", candidates}};
  }
  report["warnings"] = result.warnings;
  report["notes"] = result.notes;
  return report.dump(2);
}

std::string report_with_inputs(const std::string& report_json, const ReportInput& source, const ReportInput& target) {
  nlohmann::json report = nlohmann::json::parse(report_json);
  report["inputs"] = {{"source", {{"file", source.file}, {"sha256", source.sha256}}},
                      {"target", {{"file", target.file}, {"sha256", target.sha256}}}};
  return report.dump(2);
}

}  // namespace isocorr
