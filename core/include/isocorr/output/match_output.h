// What a match hands to its user, part by part: the dense maps both ways, their
// per-vertex confidence and the JSON report. The server stores these parts, streams them
// and the client downloads them into this same type; the part names are these.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "isocorr/transfer/surface_point.h"

namespace isocorr {

enum class ResultPart {
  kForwardMap, kReverseMap, kForwardConfidence, kReverseConfidence, kReport, kForwardPrecise, kReversePrecise
};

inline constexpr std::array<ResultPart, 7> kAllResultParts = {
    ResultPart::kForwardMap,     ResultPart::kReverseMap, ResultPart::kForwardConfidence,
    ResultPart::kReverseConfidence, ResultPart::kReport, ResultPart::kForwardPrecise,
    ResultPart::kReversePrecise};

// The parts every stored result has; results stored before precise maps lack the others.
inline constexpr std::array<ResultPart, 5> kFirstResultParts = {
    ResultPart::kForwardMap, ResultPart::kReverseMap, ResultPart::kForwardConfidence,
    ResultPart::kReverseConfidence, ResultPart::kReport};

// "forward", "reverse", "forward_confidence", "reverse_confidence", "report",
// "forward_precise", "reverse_precise".
std::string_view result_part_name(ResultPart part);

struct MatchOutput {
  // In the input files' vertex numbering.
  std::vector<int> forward;               // source vertex -> target vertex
  std::vector<int> reverse;               // target vertex -> source vertex
  // Per pair, lower is better: the spectral residual of a refined map, d_iso against the
  // anchors for the C2F map (refine = none).
  std::vector<float> forward_confidence;
  std::vector<float> reverse_confidence;
  // Each source (target) vertex's point on the other mesh: a face of the file and its
  // corners' weights (precise_map.h); face -1 where a vertex has no counterpart.
  PreciseMap forward_precise, reverse_precise;
  std::string report_json;                // the same report as `isocorr match --report`
};

}  // namespace isocorr
