// Scores of a map, intrinsic (no ground truth) and against ground truth, as the papers
// measure them (paper 001 Sec. 5; Kim et al. 2011; SHREC'20 coverage, paper 003 Alg. 1).
#pragma once

#include <string>
#include <vector>

#include "isocorr/eval/ground_truth.h"
#include "isocorr/geodesic/fast_marching.h"
#include "isocorr/transfer/precise_map.h"

namespace isocorr {

struct GroundTruthScore {
  int evaluated = 0;            // ground-truth pairs scored
  double mean_error = 0;        // D_grd: mean geodesic error / target geodesic diameter
  double max_error = 0;         // d_grd-dagger
  double mean_kim_error = 0;    // mean error / sqrt(target area)
  std::vector<double> kim_thresholds;  // r in [0, 0.25]
  std::vector<double> kim_curve;       // fraction of points with error / sqrt(area) <= r
  double kim_auc = 0;           // mean of the curve (area under it, normalised to [0, 1])
  double mirrored_fraction = -1;  // fraction of points nearer their mirror image (-1: no symmetry GT)
  double far_fraction = 0;      // fraction with error > 0.2 of the diameter
  bool flip_free = false;
  std::string flip_rule;        // the rule used, stated beside every figure
  // Per scored point: its source vertex, its error / diameter, nearer its mirror image.
  std::vector<int> point_sources;
  std::vector<double> point_errors;
  std::vector<char> point_nearer_mirror;
};

struct EvaluationOptions {
  int max_points = 2000;        // ground-truth pairs scored (evenly strided); 0 = all
  int threads = 0;
  // When given, each error is measured from the source vertex's point on the target (the
  // corners' geodesic distances to the true vertex, interpolated by the point's weights)
  // instead of from its vertex; the vertex map passed beside it is its nearest corners.
  const PreciseMap* precise = nullptr;
};

// `target_diameter` normalises D_grd. `forward` maps every source vertex (file numbering)
// to a target vertex; the target mesh must be in the file's numbering too.
GroundTruthScore score_against_ground_truth(const TriangleMesh& target, const FastMarching& target_geodesics,
                                            double target_diameter, const std::vector<int>& forward,
                                            const GroundTruth& truth, const EvaluationOptions& options);

// SHREC'20 coverage: for each n in `seed_counts`, the fraction of target area whose
// Voronoi cell around n farthest-point seeds holds at least one image of `forward`.
std::vector<double> coverage(const TriangleMesh& target, const FastMarching& target_geodesics,
                             const std::vector<int>& forward, const std::vector<int>& seed_counts);

// The same for a map whose true image is only part of the target (a partial source): of the
// area in cells (`seed_count` farthest-point seeds) that hold one of `true_images`, the share
// whose cells also hold an image of `forward`. 1 when the map reaches everywhere its true
// image does; dividing whole-target coverage by the kept share instead overshoots 1, as the
// cells along the cut reach past it.
double coverage_of_true_image(const TriangleMesh& target, const FastMarching& target_geodesics,
                              const std::vector<int>& forward, const std::vector<int>& true_images, int seed_count);

}  // namespace isocorr
