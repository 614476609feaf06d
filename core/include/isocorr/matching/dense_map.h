// The dense level: every vertex of each mesh gets an image on the other.
//
// Once the chosen map has ~250 reliable pairs, each vertex is described by its normalised
// geodesic distances to E anchor samples, and its image is the vertex of the other mesh
// with the least d_iso against those anchors (the L1 distance of the two descriptors, /E).
// Instead of further combinatorial patch levels the search is a greedy descent on the
// other mesh started from a neighbour's image and widened to the two-ring when it stops,
// so its cost is O(V * E) after O(E) geodesic fields per mesh: O(V log V) overall.
#pragma once

#include <vector>

#include "isocorr/matching/flip_tracking.h"

namespace isocorr {

struct DenseOptions {
  int anchor_count = 100;  // E
  double outlier_fraction = 0.2;     // at most this share of the tracked pairs is dropped as
                                     // anchors: those least consistent with the others,
  double outlier_ratio = 1.0;        // and only where their distortion exceeds this many medians
                                     // (1: the share, by rank, but none when all pairs agree)
  int anchor_refinement_rounds = 2;  // rounds moving anchor images to vertex accuracy
  double locality = 0.05;  // anchors weigh 1 / (distance + locality): near ones count more
                           // (0 = plain d_iso); distances are fractions of the diameter
};

struct DenseMap {
  std::vector<int> forward;              // clean source vertex -> clean target vertex
  std::vector<float> forward_diso;       // d_iso of each forward pair (confidence: lower = better)
  std::vector<int> reverse;              // clean target vertex -> clean source vertex
  std::vector<float> reverse_diso;
};

DenseMap compute_dense_map(const PreprocessedShape& source, const PreprocessedShape& target,
                           const std::vector<SamplePair>& pairs, const DenseOptions& options,
                           const JobControl& control);

}  // namespace isocorr
