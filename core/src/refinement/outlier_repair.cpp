#include "isocorr/refinement/outlier_repair.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "isocorr/matching/surface_descent.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

// The first samples of the hierarchy are spread over the whole shape.
constexpr int kAnchors = 64;
// An anchor whose median disagreement with the other anchors exceeds this many times the
// anchors' median (plus a floor for exact copies, where the median is 0) is misplaced.
constexpr double kAnchorFactor = 2;
constexpr double kAnchorFloor = 1e-3;
// Flag and accept thresholds (outlier_repair.h). Measured on 9 development pairs: with
// 2 x the median and any gain beyond the median, non-isometric stretch was flagged too
// (10-22% of SCAPE and TOSCA cat and dog vertices, D_grd 0.0157 -> 0.0178 on SCAPE 000 ->
// 004); with 4 x and halving, only misplaced regions move (FAUST 5k 004 -> 014: 3% of the
// vertices, 0.0268 -> 0.0131; the 7 other pairs unchanged or within 0.0002).
constexpr double kFlagFactor = 4;
constexpr double kAcceptFactor = 0.5;

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace

OutlierRepair repair_outliers(const PreprocessedShape& source, const PreprocessedShape& target,
                              std::vector<int>& forward, int threads, const JobControl& control) {
  threads = resolve_thread_count(threads);
  const int n = source.mesh().num_vertices();
  const int candidates = std::min(kAnchors, source.num_samples());
  const size_t m = static_cast<size_t>(target.mesh().num_vertices());

  // Distances on the target from every candidate anchor's image, / the target's diameter.
  std::vector<float> target_fields(candidates * m);
  std::vector<FastMarching::Workspace> workspaces(threads);
  const float inverse_diameter = static_cast<float>(1.0 / target.diameter());
  parallel_for(candidates, threads, [&](int a, int worker) {
    control.check_cancelled();
    auto& ws = workspaces[worker];
    target.geodesics().compute({forward[source.sample_vertex(a)]}, ws);
    float* row = target_fields.data() + a * m;
    for (size_t w = 0; w < m; ++w) row[w] = ws.distance[w] == kUnreached ? 1.f : ws.distance[w] * inverse_diameter;
  });
  auto target_field = [&](int a, int w) { return target_fields[a * m + w]; };

  std::vector<double> consistency(candidates);
  for (int a = 0; a < candidates; ++a) {
    std::vector<double> gaps;
    for (int b = 0; b < candidates; ++b)
      if (b != a)
        gaps.push_back(std::abs(source.sample_field(a, b) - target_field(a, forward[source.sample_vertex(b)])));
    consistency[a] = median(std::move(gaps));
  }
  const double anchor_limit = kAnchorFactor * median(consistency) + kAnchorFloor;
  std::vector<int> anchors;
  for (int a = 0; a < candidates; ++a)
    if (consistency[a] <= anchor_limit) anchors.push_back(a);

  OutlierRepair report;
  report.anchors = static_cast<int>(anchors.size());
  if (anchors.empty()) return report;
  // A vertex's distances to the anchors, read once per vertex (a column of the fields).
  using AnchorDistances = std::array<float, kAnchors>;
  const size_t anchor_count = anchors.size();
  auto gather = [&](int v, AnchorDistances& at_source) {
    for (size_t k = 0; k < anchor_count; ++k) at_source[k] = source.field(anchors[k], v);
  };
  auto distortion = [&](const AnchorDistances& at_source, int w) {
    double sum = 0;
    for (size_t k = 0; k < anchor_count; ++k) sum += std::abs(at_source[k] - target_field(anchors[k], w));
    return sum / anchor_count;
  };
  std::vector<double> current(n);
  parallel_for(n, threads, [&](int v, int) {
    AnchorDistances at_source;
    gather(v, at_source);
    current[v] = distortion(at_source, forward[v]);
  });
  report.median_distortion = median(current);
  std::vector<int> flagged;
  for (int v = 0; v < n; ++v)
    if (current[v] > kFlagFactor * report.median_distortion) flagged.push_back(v);
  report.flagged = static_cast<int>(flagged.size());
  control.check_cancelled();

  // The search reads every offered sample's distances to the anchors in a row, and a sample
  // is dropped as soon as its partial sum exceeds the best mean so far: the terms are
  // non-negative, so the result is the full search's (michael's 52K pair flags thousands of
  // vertices in some candidates, and each read a column of the fields before).
  const std::vector<int>& offered = target.spectral_samples();
  std::vector<float> offered_fields(offered.size() * anchor_count);
  for (size_t s = 0; s < offered.size(); ++s)
    for (size_t k = 0; k < anchor_count; ++k)
      offered_fields[s * anchor_count + k] = target_field(anchors[k], offered[s]);
  // Rounding slack on the bound, so that a sample is dropped only when it cannot win.
  constexpr double kBoundSlack = 1 + 1e-9;
  std::vector<int> moved_to(flagged.size(), -1);
  parallel_for(static_cast<int>(flagged.size()), threads, [&](int i, int) {
    const int v = flagged[i];
    AnchorDistances at_source;
    gather(v, at_source);
    int best = forward[v];
    double best_distortion = current[v];
    double bound = best_distortion * anchor_count * kBoundSlack;
    for (size_t s = 0; s < offered.size(); ++s) {
      const float* row = offered_fields.data() + s * anchor_count;
      double sum = 0;
      size_t k = 0;
      for (; k < anchor_count && sum <= bound; ++k) sum += std::abs(at_source[k] - row[k]);
      if (k < anchor_count) continue;
      const double d = sum / anchor_count;
      if (d < best_distortion) {
        best_distortion = d, best = offered[s];
        bound = best_distortion * anchor_count * kBoundSlack;
      }
    }
    float reached = 0;
    best = descend_to_minimum<CostPrice::kDear>(target.geodesics().topology(), best,
                              [&](int w) { return static_cast<float>(distortion(at_source, w)); }, reached);
    if (reached < kAcceptFactor * current[v] - report.median_distortion) moved_to[i] = best;
  });
  for (size_t i = 0; i < flagged.size(); ++i) {
    if (moved_to[i] < 0) continue;
    forward[flagged[i]] = moved_to[i];
    ++report.moved;
  }
  return report;
}

}  // namespace isocorr
