#include "isocorr/output/match_output.h"

namespace isocorr {

std::string_view result_part_name(ResultPart part) {
  switch (part) {
    case ResultPart::kForwardMap: return "forward";
    case ResultPart::kReverseMap: return "reverse";
    case ResultPart::kForwardConfidence: return "forward_confidence";
    case ResultPart::kReverseConfidence: return "reverse_confidence";
    case ResultPart::kReport: return "report";
    case ResultPart::kForwardPrecise: return "forward_precise";
    case ResultPart::kReversePrecise: return "reverse_precise";
  }
  return "unknown";
}

}  // namespace isocorr
