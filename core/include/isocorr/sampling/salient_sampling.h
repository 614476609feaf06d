// Evenly spaced salient sampling (docs/algorithm.md, per-mesh preprocessing), for all levels at once.
//
// Vertices are visited by decreasing saliency and accepted when they lie at least the
// level's radius (geodesic) from every sample accepted so far. Radii shrink level by level,
// so each level adds samples between the earlier ones and the accepted set is a hierarchy.
#pragma once

#include <vector>

#include "isocorr/geodesic/fast_marching.h"

namespace isocorr {

struct SamplingSchedule {
  std::vector<double> radii;   // absolute geodesic radius of each step, decreasing
  std::vector<int> max_new;    // cap on samples added at each step (<= 0: no cap)
};

struct SampleSet {
  std::vector<int> vertices;   // samples in acceptance order
  std::vector<int> step;       // schedule step at which each sample was accepted
};

// `order` is the saliency order (most salient first). Deterministic.
SampleSet evenly_spaced_salient_sampling(const FastMarching& geodesics,
                                         const std::vector<int>& order,
                                         const SamplingSchedule& schedule);

}  // namespace isocorr
