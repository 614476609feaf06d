#include "part_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "isocorr/shape/mean_curvature.h"
#include "isocorr/util/error.h"
#include "isocorr/util/parallel.h"

namespace isocorr {

std::vector<float> distance_to_boundary(const PreprocessedShape& shape) {
  const TriangleMesh& mesh = shape.mesh();
  const std::vector<int> boundary = boundary_vertices(mesh);
  if (boundary.empty()) return std::vector<float>(mesh.num_vertices(), kUnreached);
  FastMarching::Workspace workspace;
  shape.geodesics().compute(boundary, workspace);
  return workspace.distance;
}

// A cut makes false extremities along its rim; a shape with fewer than 3 extremities left
// (half a body may keep only a leg) takes further samples, which are not extremities.
std::vector<int> search_samples(const PreprocessedShape& s, const std::vector<float>& boundary_distance,
                                float rim_band, int wanted, bool& not_all_extremities) {
  const std::vector<int>& extremities = s.saliency().extremities;
  auto away = [&](int i) { return boundary_distance[s.sample_vertex(i)] >= rim_band; };
  std::vector<int> chosen;
  for (int i = 0; i < s.num_level0_samples() && static_cast<int>(chosen.size()) < wanted; ++i)
    if (away(i) && std::find(extremities.begin(), extremities.end(), s.sample_vertex(i)) != extremities.end())
      chosen.push_back(i);
  not_all_extremities = chosen.size() < 3;
  for (int i = 0; i < s.num_samples() && chosen.size() < 3; ++i)
    if (away(i) && std::find(chosen.begin(), chosen.end(), i) == chosen.end()) chosen.push_back(i);
  if (chosen.size() < 3) throw InputError("a partial shape has fewer than 3 samples away from its boundary to match");
  return chosen;
}

// The paper's scale-invariant distortion, made boundary-aware: the scale kappa is the mean
// source/target ratio over the pairs exact on both shapes, and each pair adds its relative
// mismatch at that scale (one-sided where a distance is only an upper bound). The paper's
// ratio-spread form over exact pairs alone leaves an extremity free whenever a cut makes
// all its distances inexact, so maps differing only there tie.
double scale_invariant_distortion(const std::vector<std::vector<double>>& gs, const Eigen::MatrixXd& gt,
                                  const std::vector<std::vector<char>>& exact,
                                  const std::vector<std::vector<char>>& target_exact,
                                  const std::vector<int>& target_of, double& scale) {
  const int m = static_cast<int>(target_of.size());
  double ratio_sum = 0, least_ratio = std::numeric_limits<double>::max();
  int ratios = 0;
  for (int i = 0; i < m; ++i)
    for (int a = i + 1; a < m; ++a) {
      const double r = gs[i][a] / std::max(gt(target_of[i], target_of[a]), 1e-12);
      const bool target_side_exact = target_exact[target_of[i]][target_of[a]];
      if (exact[i][a] && target_side_exact) ratio_sum += r, ++ratios;
      else if (target_side_exact) least_ratio = std::min(least_ratio, r);  // source lengthened: r >= kappa
    }
  // Without exact pairs the ratios of lengthened source distances bound kappa from above;
  // the tightest bound is the best guess.
  scale = ratios ? ratio_sum / ratios : least_ratio == std::numeric_limits<double>::max() ? 1.0 : least_ratio;
  double sum = 0;
  for (int i = 0; i < m; ++i)
    for (int a = i + 1; a < m; ++a)
      sum += mismatch(static_cast<float>(gs[i][a]), static_cast<float>(scale * gt(target_of[i], target_of[a])),
                      exact[i][a], target_exact[target_of[i]][target_of[a]]) /
             std::max(gs[i][a], 1e-12);
  return sum / std::max(1, m * (m - 1) / 2);
}

// The smoothing spreads what the rim does to the curvature over a few smoothing lengths;
// twice the largest keeps the compared points out of it.
constexpr double kRimReachInLengths = 2.0;
// Kappas within this ratio share one smoothing of the part.
constexpr double kScaleStep = 1.02;

int PartCurvature::key(double scale) { return static_cast<int>(std::lround(std::log(scale) / std::log(kScaleStep))); }

PartCurvature::PartCurvature(const PartGeometry& part, const std::vector<double>& scales, int threads)
    : part_(part) {
  if (part.target.smoothed_curvature().cols() == 0) return;  // no spectral preprocessing: nothing to compare
  for (const double scale : scales)
    if (scale > 0 && std::isfinite(scale)) at_scale_[key(scale)];
  std::vector<std::pair<const int, AtScale>*> slots;
  for (auto& slot : at_scale_) slots.push_back(&slot);
  parallel_for(static_cast<int>(slots.size()), threads, [&](int i, int) {
    const double scale = std::pow(kScaleStep, slots[i]->first);
    const double length = std::sqrt(part.target.area()) * scale;  // the whole's sqrt(area), in part units
    AtScale& at = slots[i]->second;
    at.curvature = smoothed_mean_curvature(part.shape.mesh(), part.shape.normals(), kCurvatureScales, length);
    at.source_band = static_cast<float>(kRimReachInLengths * kCurvatureScales.back() * length);
    at.target_band = static_cast<float>(at.source_band / scale);
  });
}

double PartCurvature::disagreement(const std::vector<int>& forward, double scale) const {
  if (at_scale_.empty()) return 0;  // no spectral preprocessing: no curvature to compare
  const auto found = scale > 0 && std::isfinite(scale) ? at_scale_.find(key(scale)) : at_scale_.end();
  // A map must not look perfect because its kappa was not among those smoothed for.
  if (found == at_scale_.end()) throw std::logic_error("PartCurvature: kappa not among those given");
  const AtScale& at = found->second;
  std::vector<std::pair<int, int>> pairs, all;
  for (const int v : part_.shape.spectral_samples()) {
    all.emplace_back(v, forward[v]);
    if (part_.boundary_distance[v] >= at.source_band && part_.target_boundary_distance[forward[v]] >= at.target_band)
      pairs.emplace_back(v, forward[v]);
  }
  return curvature_disagreement(at.curvature, part_.target.smoothed_curvature(), pairs.empty() ? all : pairs);
}

}  // namespace isocorr
