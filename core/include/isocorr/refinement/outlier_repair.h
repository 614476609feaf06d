// Moves the vertices of a refined map that landed in the wrong place entirely.
//
// A spectral map can send a small region (a raised hand, a head) to another part of the
// body while the rest is right: the region's embedding is ambiguous and the functional map
// settles on the wrong copy. Such a region is a few per cent of the points but most of the
// error (FAUST 5k tr_reg_007 -> 017: 5% of the points held 55% of it), and the rigidity
// polish would spread it (there 0.027 -> 0.044).
//
// The map's coarse samples, minus those that disagree with the others, serve as anchors:
// each vertex's distortion is the mean |g_S(v, a) - g_T(F(v), F(a))| over the anchors. A
// non-isometric stretch spreads distortion over the whole body; a misplaced region stands
// out. Vertices whose distortion exceeds kFlagFactor times the map's median are searched
// for again over the target (its spectral samples, then descent), and move only when a
// target vertex halves their distortion and beats it by the median.
#pragma once

#include <vector>

#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

struct OutlierRepair {
  int anchors = 0;  // anchors kept
  int flagged = 0;  // vertices searched again
  int moved = 0;    // vertices given a new image
  double median_distortion = 0;
};

// `forward` (every source vertex -> target vertex, clean numbering) is changed in place.
// Costs one fast-marching field per anchor on the target. Deterministic.
OutlierRepair repair_outliers(const PreprocessedShape& source, const PreprocessedShape& target,
                              std::vector<int>& forward, int threads, const JobControl& control = {});

}  // namespace isocorr
