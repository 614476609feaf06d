// Step 4 of the part search (part_matching.h): a grown sample map extended to every source
// vertex by descent of its anchors' weighted mismatch on the target, and what is measured
// of the result (the share of the target it covers).
#pragma once

#include <vector>

#include "isocorr/matching/dense_map.h"
#include "isocorr/matching/flip_tracking.h"
#include "isocorr/util/progress.h"
#include "part_geometry.h"

namespace isocorr {

// Order in which source vertices are visited: breadth first from the first extremity (every
// candidate's first pair), so each vertex's descent starts at the image of a neighbour; each
// vertex's parent is the neighbour it was reached from (-1 for the first).
struct VisitOrder {
  std::vector<int> order;
  std::vector<int> parent;
};

VisitOrder breadth_first_order(const PreprocessedShape& shape, int start);

// The vertices a rough candidate's map is made on when its finalists are finished (and its
// dense map made then): the spectral samples, where its curvature is compared, and the
// faces around every fourth of them, where its orientation is (a 28K-vertex part: about
// 5000 of its vertices).
std::vector<char> rough_map_vertices(const PreprocessedShape& source);

// A rough map's vertices left out (-1) take the image of their visit parent, so that the
// candidate's map kept for the report is defined everywhere.
void fill_from_parents(const VisitOrder& visit, int fallback, std::vector<int>& forward);

// The target side of the dense anchors: each pair's image and its distance field, either
// the target's sample fields (cheap: for comparing candidates) or fields computed from
// vertex-accurate images (for the chosen map).
struct TargetAnchors {
  std::vector<int> vertex;
  std::vector<const float*> rows;  // distance to every target vertex, times row_scale = raw
  float row_scale = 1;
  std::vector<std::vector<float>> computed_fields;
};

TargetAnchors sample_anchors(const PreprocessedShape& target, const std::vector<SamplePair>& pairs);

// Each pair's image moved from its target sample to the vertex that best agrees with the
// other pairs (a sample spacing is about 4% of the diameter: too coarse for the dense map),
// then a geodesic field from each moved image.
TargetAnchors vertex_accurate_anchors(const PartGeometry& part, const std::vector<SamplePair>& pairs, double scale,
                                      int threads, const JobControl& control);

// Every source vertex in `visit` order, or only those `wanted` (when not empty; the rest
// -1), by descent of the anchors' weighted mismatch on the target (the forward map only).
DenseMap dense_part_map(const PartGeometry& part, const TrackedMap& chosen, const TargetAnchors& anchors, double scale,
                        const VisitOrder& visit, const std::vector<char>& wanted, const JobControl& control);

// The share of the part's expected image area (area(part) / kappa^2) that its dense map
// covers on the target (a few edge lengths around each image, as the reverse map marks
// it); fills map's reverse map.
double covered_share(const PreprocessedShape& source, const PreprocessedShape& target,
                     const std::vector<double>& target_vertex_areas, double scale, DenseMap& map);

}  // namespace isocorr
