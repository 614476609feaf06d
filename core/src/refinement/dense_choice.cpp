#include "isocorr/refinement/dense_choice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "isocorr/matching/orientation.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

// The coarse samples come first in the hierarchy, so the first ones are spread over the
// whole shape: distant pairs are where a turned map shows.
constexpr int kDistortionTargets = 64;

}  // namespace

DenseEvidence measure_dense_map(const PreprocessedShape& source, const PreprocessedShape& target,
                                const std::vector<int>& forward, const std::vector<int>& reverse,
                                int distortion_sources, int threads) {
  DenseEvidence evidence;
  evidence.orientation =
      dense_orientation_agreement(source.mesh(), source.normals(), target.mesh(), target.normals(), forward);

  const int targets = std::min(kDistortionTargets, source.num_samples());
  const int sources = std::min(distortion_sources, targets);
  threads = resolve_thread_count(threads);
  std::vector<FastMarching::Workspace> workspaces(threads);
  std::vector<double> sums(sources, 0.0);
  const double inverse_diameter = 1.0 / target.diameter();
  parallel_for(sources, threads, [&](int a, int worker) {
    auto& ws = workspaces[worker];
    target.geodesics().compute({forward[source.sample_vertex(a)]}, ws);
    for (int b = 0; b < targets; ++b) {
      if (b == a) continue;
      const float reached = ws.distance[forward[source.sample_vertex(b)]];
      const double d_target = reached == kUnreached ? 1.0 : reached * inverse_diameter;
      sums[a] += std::abs(source.field(a, source.sample_vertex(b)) - d_target);
    }
  });
  double total = 0;
  for (double s : sums) {
    total += s;
    evidence.distortion_max = std::max(evidence.distortion_max, s / std::max(1, targets - 1));
  }
  evidence.distortion = sources > 0 ? total / (static_cast<double>(sources) * (targets - 1)) : 0.0;

  double round_trip = 0;
  for (int b = 0; b < targets; ++b) round_trip += source.field(b, reverse[forward[source.sample_vertex(b)]]);
  evidence.round_trip = targets > 0 ? round_trip / targets : 0.0;
  return evidence;
}

int choose_dense_candidate(std::vector<DenseCandidate>& candidates, double orientation_margin, std::string& why) {
  double best_orientation = 0;
  for (const auto& c : candidates) best_orientation = std::max(best_orientation, c.evidence.orientation);
  int winner = -1;
  for (int i = 0; i < static_cast<int>(candidates.size()); ++i) {
    DenseCandidate& c = candidates[i];
    c.score = c.evidence.distortion + c.evidence.round_trip;
    c.mirrored = c.evidence.orientation < best_orientation - orientation_margin;
    if (!c.mirrored && (winner < 0 || c.score < candidates[winner].score)) winner = i;
  }
  char text[200];
  std::snprintf(text, sizeof text,
                "least distortion + round trip (%.4f) among the %d of %d refined candidates whose orientation "
                "is within %.2f of the best (%.3f)",
                candidates[winner].score,
                static_cast<int>(std::count_if(candidates.begin(), candidates.end(),
                                               [](const DenseCandidate& c) { return !c.mirrored; })),
                static_cast<int>(candidates.size()), orientation_margin, best_orientation);
  why = text;
  return winner;
}

}  // namespace isocorr
