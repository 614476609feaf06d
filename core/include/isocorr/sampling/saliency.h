// Per-vertex saliency: extremities first, then average geodesic distance (AGD).
//
// The prototype measurements (docs/decisions.md) found "extremities first (local maxima of
// AGD), then AGD" the best ordering for level-0 samples and plain |Gaussian curvature|
// the worst, so that is the order used here.
#pragma once

#include <vector>

#include "isocorr/geodesic/fast_marching.h"
#include "isocorr/util/progress.h"

namespace isocorr {

struct SaliencyOptions {
  int agd_sources = 24;            // farthest-point sources whose mean field approximates AGD
  double extremity_radius = 0.08;  // an extremity is the AGD maximum within this geodesic
                                   // radius (fraction of the geodesic diameter)
};

struct Saliency {
  std::vector<float> agd;          // #V, average geodesic distance / diameter
  std::vector<int> extremities;    // vertices, by decreasing AGD
  std::vector<int> order;          // all vertices, most salient first
  double diameter = 0;             // geodesic diameter estimate (largest distance seen;
                                   // PreprocessedShape refines it over all sample fields)
};

// Computes AGD from farthest-point fields, the diameter estimate, extremities and the
// saliency order. Deterministic for a given mesh.
// `control` is checked between fields.
Saliency compute_saliency(const FastMarching& geodesics, const SaliencyOptions& options,
                          int threads, const JobControl& control = {});

}  // namespace isocorr
