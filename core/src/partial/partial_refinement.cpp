#include "isocorr/partial/partial_refinement.h"

#include <algorithm>
#include <utility>

#include "isocorr/refinement/candidate_screening.h"

namespace isocorr {
namespace {

// The part's share of the whole's area is clamped to this range: a part is at most the whole,
// and a far smaller share leaves too few part functions to fit C with.
constexpr double kLeastShare = 0.2;

}  // namespace

std::vector<int> refine_part_map_spectrally(const PreprocessedShape& part, const PreprocessedShape& whole,
                                            double scale, const ZoomOutOptions& options,
                                            const std::vector<int>& forward, const JobControl& control) {
  if (part.spectral_basis().cols() == 0 || whole.spectral_basis().cols() == 0) return forward;
  ZoomOutOptions partial = options;
  partial.commutativity = 0;
  partial.source_share = std::clamp(part.area() / (scale * scale * whole.area()), kLeastShare, 1.0);
  std::vector<std::pair<int, int>> start;
  for (const int v : part.spectral_samples()) start.emplace_back(v, forward[v]);
  return zoomout(spectral_side(part), spectral_side(whole), start, partial, control).image;
}

}  // namespace isocorr
