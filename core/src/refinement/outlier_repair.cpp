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

// Distances on the target from every candidate anchor's image, / the target's diameter.
struct AnchorImageFields {
  std::vector<float> values;  // one row of m per candidate anchor
  size_t m = 0;               // target vertices
  float at(int a, int w) const { return values[a * m + w]; }
};

AnchorImageFields anchor_image_fields(const PreprocessedShape& source, const PreprocessedShape& target,
                                      const std::vector<int>& forward, int candidates, int threads,
                                      const JobControl& control) {
  AnchorImageFields fields;
  fields.m = static_cast<size_t>(target.mesh().num_vertices());
  const size_t m = fields.m;
  fields.values.resize(candidates * m);
  std::vector<FastMarching::Workspace> workspaces(threads);
  const float inverse_diameter = static_cast<float>(1.0 / target.diameter());
  parallel_for(candidates, threads, [&](int a, int worker) {
    control.check_cancelled();
    auto& ws = workspaces[worker];
    target.geodesics().compute({forward[source.sample_vertex(a)]}, ws);
    float* row = fields.values.data() + a * m;
    for (size_t w = 0; w < m; ++w) row[w] = ws.distance[w] == kUnreached ? 1.f : ws.distance[w] * inverse_diameter;
  });
  return fields;
}

// The candidate anchors that agree with the others.
std::vector<int> consistent_anchors(const PreprocessedShape& source, const AnchorImageFields& target_fields,
                                    const std::vector<int>& forward, int candidates) {
  std::vector<double> consistency(candidates);
  for (int a = 0; a < candidates; ++a) {
    std::vector<double> gaps;
    for (int b = 0; b < candidates; ++b)
      if (b != a)
        gaps.push_back(std::abs(source.sample_field(a, b) - target_fields.at(a, forward[source.sample_vertex(b)])));
    consistency[a] = median(std::move(gaps));
  }
  const double anchor_limit = kAnchorFactor * median(consistency) + kAnchorFloor;
  std::vector<int> anchors;
  for (int a = 0; a < candidates; ++a)
    if (consistency[a] <= anchor_limit) anchors.push_back(a);
  return anchors;
}

// A vertex's distances to the anchors, read once per vertex (a column of the fields).
using AnchorDistances = std::array<float, kAnchors>;

// The mean distortion of a pair (v, w) against the anchors.
struct AnchorDistortion {
  const PreprocessedShape& source;
  const AnchorImageFields& target_fields;
  const std::vector<int>& anchors;

  void gather(int v, AnchorDistances& at_source) const {
    for (size_t k = 0; k < anchors.size(); ++k) at_source[k] = source.field(anchors[k], v);
  }
  double operator()(const AnchorDistances& at_source, int w) const {
    const size_t anchor_count = anchors.size();
    double sum = 0;
    for (size_t k = 0; k < anchor_count; ++k) sum += std::abs(at_source[k] - target_fields.at(anchors[k], w));
    return sum / anchor_count;
  }
};

// Every vertex's distortion under `forward`, in `current`; the map's median in the report,
// and the vertices beyond kFlagFactor times it.
std::vector<int> flag_outliers(const AnchorDistortion& distortion, const std::vector<int>& forward, int threads,
                               std::vector<double>& current, OutlierRepair& report) {
  const int n = distortion.source.mesh().num_vertices();
  current.resize(n);
  parallel_for(n, threads, [&](int v, int) {
    AnchorDistances at_source;
    distortion.gather(v, at_source);
    current[v] = distortion(at_source, forward[v]);
  });
  report.median_distortion = median(current);
  std::vector<int> flagged;
  for (int v = 0; v < n; ++v)
    if (current[v] > kFlagFactor * report.median_distortion) flagged.push_back(v);
  report.flagged = static_cast<int>(flagged.size());
  return flagged;
}

// Each flagged vertex's new image, or -1 where none halves its distortion and beats it by
// the median: the least distortion over the target's spectral samples, then descent.
std::vector<int> search_again(const PreprocessedShape& target, const AnchorDistortion& distortion,
                              const std::vector<int>& flagged, const std::vector<double>& current,
                              const std::vector<int>& forward, double median_distortion, int threads) {
  const size_t anchor_count = distortion.anchors.size();
  // The search reads every offered sample's distances to the anchors in a row, and a sample
  // is dropped as soon as its partial sum exceeds the best mean so far: the terms are
  // non-negative, so the result is the full search's (michael's 52K pair flags thousands of
  // vertices in some candidates, and each read a column of the fields before).
  const std::vector<int>& offered = target.spectral_samples();
  std::vector<float> offered_fields(offered.size() * anchor_count);
  for (size_t s = 0; s < offered.size(); ++s)
    for (size_t k = 0; k < anchor_count; ++k)
      offered_fields[s * anchor_count + k] = distortion.target_fields.at(distortion.anchors[k], offered[s]);
  // Rounding slack on the bound, so that a sample is dropped only when it cannot win.
  constexpr double kBoundSlack = 1 + 1e-9;
  std::vector<int> moved_to(flagged.size(), -1);
  parallel_for(static_cast<int>(flagged.size()), threads, [&](int i, int) {
    const int v = flagged[i];
    AnchorDistances at_source;
    distortion.gather(v, at_source);
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
    if (reached < kAcceptFactor * current[v] - median_distortion) moved_to[i] = best;
  });
  return moved_to;
}

}  // namespace

OutlierRepair repair_outliers(const PreprocessedShape& source, const PreprocessedShape& target,
                              std::vector<int>& forward, int threads, const JobControl& control) {
  threads = resolve_thread_count(threads);
  const int candidates = std::min(kAnchors, source.num_samples());
  const AnchorImageFields target_fields = anchor_image_fields(source, target, forward, candidates, threads, control);
  const std::vector<int> anchors = consistent_anchors(source, target_fields, forward, candidates);
  OutlierRepair report;
  report.anchors = static_cast<int>(anchors.size());
  if (anchors.empty()) return report;
  const AnchorDistortion distortion{source, target_fields, anchors};
  std::vector<double> current;
  const std::vector<int> flagged = flag_outliers(distortion, forward, threads, current, report);
  control.check_cancelled();
  const std::vector<int> moved_to =
      search_again(target, distortion, flagged, current, forward, report.median_distortion, threads);
  for (size_t i = 0; i < flagged.size(); ++i) {
    if (moved_to[i] < 0) continue;
    forward[flagged[i]] = moved_to[i];
    ++report.moved;
  }
  return report;
}

}  // namespace isocorr
