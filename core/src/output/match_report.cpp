#include "isocorr/output/match_report.h"

#include <algorithm>

#include <nlohmann/json.hpp>

namespace isocorr {

std::string match_report_json(const MatchResult& result, const MatchSettings& settings) {
  using nlohmann::json;
  json report;
  report["settings"] = {
      {"level0_samples", settings.level0_samples},
      {"level0_extra_targets", settings.level0_extra_targets},
      {"max_level0_diso", settings.max_level0_diso},
      {"min_tracked", settings.min_tracked},
      {"max_tracked", settings.max_tracked},
      {"selection", settings.selection == SelectionRule::kLeastDistortion ? "least-diso" : "orientation"},
      {"orientation_threshold", settings.orientation_threshold},
      {"orientation_margin", settings.orientation_margin},
      {"anchor_cap", settings.tracking.anchor_cap},
      {"window_factor", settings.tracking.window_factor},
      {"trim_fraction", settings.tracking.trim_fraction},
      {"dense_anchors", settings.dense.anchor_count},
      {"level0_radius", settings.preprocess.level0_radius},
      {"level_shrink", settings.preprocess.level_shrink},
      {"decision_level", settings.preprocess.decision_level},
  };
  json timings = json::object();
  double total = 0;
  for (const auto& t : result.timings) timings[t.stage] = t.seconds, total += t.seconds;
  timings["total"] = total;
  report["timings_seconds"] = timings;

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
  report["final"] = {{"diso", result.diso}, {"diso_max", result.diso_max},
                     {"orientation", result.dense_orientation},
                     {"source_vertices", result.forward.size()},
                     {"target_vertices", result.reverse.size()}};
  report["notes"] = result.notes;
  return report.dump(2);
}

}  // namespace isocorr
