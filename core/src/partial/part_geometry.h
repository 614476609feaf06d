// Distances between two shapes either of which may be partial, and what they are worth:
// shared by the part search (part_*.cpp) and RAVAC (ravac.cpp).
//
// Removing surface can only lengthen geodesics, and only those whose path could touch the
// cut: a distance g(x, y) on a shape with a boundary is the complete shape's when
// g(x, y) < b(x) + b(y), b = distance to the boundary; otherwise it is an upper bound. A
// closed shape has b = +inf, so all its distances are exact.
#pragma once

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include <Eigen/Core>

#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

// Raw geodesic distance from every vertex to the shape's boundary (+inf when closed).
std::vector<float> distance_to_boundary(const PreprocessedShape& shape);

struct PartGeometry {
  const PreprocessedShape& shape;   // the source
  std::vector<float> boundary_distance;
  const PreprocessedShape& target;
  std::vector<float> target_boundary_distance;

  PartGeometry(const PreprocessedShape& source, const PreprocessedShape& target_shape)
      : shape(source),
        boundary_distance(distance_to_boundary(source)),
        target(target_shape),
        target_boundary_distance(distance_to_boundary(target_shape)) {}

  // Raw geodesic distance from source sample i to source vertex v.
  float distance(int sample, int v) const { return shape.field(sample, v) * static_cast<float>(shape.diameter()); }
  // True when the source's distance d between sample i and vertex v is the complete shape's.
  bool exact(int sample, int v, float d) const {
    return d < boundary_distance[shape.sample_vertex(sample)] + boundary_distance[v];
  }
  // The same on the target, between two target vertices (d raw).
  bool target_exact(int a, int b, float d) const {
    return d < target_boundary_distance[a] + target_boundary_distance[b];
  }
};

// Mismatch of a source distance and a target distance already at the source's scale. An
// upper bound on one side only says the other may not exceed it; two bounds say nothing.
inline float mismatch(float source_distance, float target_distance, bool source_exact, bool target_exact) {
  const float gap = target_distance - source_distance;
  if (source_exact && target_exact) return std::abs(gap);
  if (source_exact) return std::max(-gap, 0.0f);
  if (target_exact) return std::max(gap, 0.0f);
  return 0.0f;
}

// Smoothed curvature compared across a cut (mean_curvature.h, dense_choice.h). The part's
// own curvature would be measured at its own sqrt(area), smaller than the whole's (0.74 of
// it for a 55% part), which shrinks its values and its smoothing lengths alike: every map,
// right or wrong, then disagrees by that much (0.19 for the true map of a 55% part of the
// test creature). Here a map of kappa (source length per target length) is judged by the
// part's curvature at the target's lengths carried to the part by that kappa: if the map is
// right, that is where the part looks like the whole. Only points beyond the smoothing's
// reach from either rim count (a cut's edge is no crease of the whole shape).
class PartCurvature {
 public:
  // The part's curvature at each kappa of `scales` to within 2% (one smoothing per distinct
  // one: the part search's candidates cluster), on `threads` workers.
  PartCurvature(const PartGeometry& part, const std::vector<double>& scales, int threads);
  // curvature_disagreement of `forward`, a map of kappa `scale`, over the source's spectral
  // samples away from both rims (all of them when none is). `scale` must be one of those
  // given (std::logic_error otherwise); 0 when the target has no curvature.
  double disagreement(const std::vector<int>& forward, double scale) const;

 private:
  struct AtScale {
    Eigen::MatrixXf curvature;
    float source_band = 0, target_band = 0;  // raw, on each shape
  };
  static int key(double scale);
  const PartGeometry& part_;
  std::map<int, AtScale> at_scale_;
};

// Extremity samples this close to the boundary (fraction of the shape's diameter, the
// saliency's extremity radius) are the rim of a cut, not a tip of the shape.
inline constexpr double kRimBand = 0.08;

// The paper's scale-invariant distortion of a map of m points, boundary-aware: gs (m x m)
// and exact are the source's raw distances between the points and whether they are exact;
// gt and target_exact the same between target points, the map sending point i to
// target_of[i]. kappa (`scale`) is the mean source/target ratio over pairs exact on both
// shapes; each pair adds its relative mismatch at that scale.
double scale_invariant_distortion(const std::vector<std::vector<double>>& gs, const Eigen::MatrixXd& gt,
                                  const std::vector<std::vector<char>>& exact,
                                  const std::vector<std::vector<char>>& target_exact,
                                  const std::vector<int>& target_of, double& scale);

// A sparse map between samples of the two shapes, the start of a dense part map.
struct ExtremityMap {
  std::vector<int> source_samples;
  std::vector<int> target_samples;  // one per source sample
  double distortion = 0;            // scale-invariant, of the method that proposed it
  double scale = 1;                 // kappa: source distance per target distance
};

// A shape's points for the combinatorial search: its extremity samples at least
// `rim_band` (raw) from its boundary, best first, at most `wanted`; when fewer than 3,
// further samples away from the boundary (then `not_all_extremities` is set). Throws
// InputError when fewer than 3 samples lie away from the boundary.
std::vector<int> search_samples(const PreprocessedShape& shape, const std::vector<float>& boundary_distance,
                                float rim_band, int wanted, bool& not_all_extremities);

}  // namespace isocorr
