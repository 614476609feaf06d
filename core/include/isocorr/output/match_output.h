// What a match hands to its user, part by part: the dense maps both ways, their
// per-vertex confidence and the JSON report. The server stores these parts, streams them
// and the client downloads them into this same type; the part names are these.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace isocorr {

enum class ResultPart { kForwardMap, kReverseMap, kForwardConfidence, kReverseConfidence, kReport };

inline constexpr std::array<ResultPart, 5> kAllResultParts = {
    ResultPart::kForwardMap, ResultPart::kReverseMap, ResultPart::kForwardConfidence,
    ResultPart::kReverseConfidence, ResultPart::kReport};

// "forward", "reverse", "forward_confidence", "reverse_confidence", "report".
std::string_view result_part_name(ResultPart part);

struct MatchOutput {
  // In the input files' vertex numbering.
  std::vector<int> forward;               // source vertex -> target vertex
  std::vector<int> reverse;               // target vertex -> source vertex
  // Per pair, lower is better: the spectral residual of a refined map, d_iso against the
  // anchors for the C2F map (refine = none).
  std::vector<float> forward_confidence;
  std::vector<float> reverse_confidence;
  std::string report_json;                // the same report as `isocorr match --report`
};

}  // namespace isocorr
