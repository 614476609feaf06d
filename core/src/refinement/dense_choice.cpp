#include "isocorr/refinement/dense_choice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "isocorr/matching/orientation.h"
#include "isocorr/shape/mean_curvature.h"
#include "isocorr/transfer/landmarks.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

// The coarse samples come first in the hierarchy, so the first ones are spread over the
// whole shape: distant pairs are where a turned map shows.
constexpr int kDistortionTargets = 64;
constexpr double kNeighbourhoodRadius = 0.03;  // x diameter: above a refined map's error

constexpr int kSignatureTimes = 16;

// Rows: times; columns: exp(-lambda_i t) / sum_i exp(-lambda_i t), so that a point's heat
// kernel signature is this matrix times its squared basis row and the constant function
// reads 1 at every time (the basis is area-normalised: times are comparable across shapes).
Eigen::MatrixXd heat_weights(const Eigen::VectorXf& eigenvalues, const std::vector<double>& times) {
  Eigen::MatrixXd weights(times.size(), eigenvalues.size());
  for (size_t j = 0; j < times.size(); ++j) {
    weights.row(j) = (-eigenvalues.cast<double>() * times[j]).array().exp().matrix().transpose();
    weights.row(j) /= weights.row(j).sum();
  }
  return weights;
}

Eigen::VectorXd heat_signature(const PreprocessedShape& shape, const Eigen::MatrixXd& weights, int v) {
  return weights * shape.spectral_basis().row(v).cast<double>().array().square().matrix().transpose();
}

}  // namespace

double heat_signature_disagreement(const PreprocessedShape& source, const PreprocessedShape& target,
                                   const std::vector<int>& forward) {
  const Eigen::VectorXf& values = source.spectral_eigenvalues();
  if (values.size() < 3 || !(values(1) > 0) || !(values(values.size() - 1) > values(1))) return 0;
  const double t_min = 4 * std::log(10.0) / values(values.size() - 1), t_max = 4 * std::log(10.0) / values(1);
  std::vector<double> times(kSignatureTimes);
  for (int j = 0; j < kSignatureTimes; ++j)
    times[j] = t_min * std::pow(t_max / t_min, j / static_cast<double>(kSignatureTimes - 1));
  const Eigen::MatrixXd source_weights = heat_weights(values, times);
  const Eigen::MatrixXd target_weights = heat_weights(target.spectral_eigenvalues(), times);
  double total = 0;
  for (const int v : source.spectral_samples()) {
    const Eigen::VectorXd hs = heat_signature(source, source_weights, v);
    const Eigen::VectorXd ht = heat_signature(target, target_weights, forward[v]);
    total += ((hs - ht).array().abs() / (hs + ht).array().max(1e-12)).sum();
  }
  return total / (kSignatureTimes * std::max<size_t>(1, source.spectral_samples().size()));
}

double curvature_disagreement(const PreprocessedShape& source, const PreprocessedShape& target,
                              const std::vector<int>& forward) {
  std::vector<std::pair<int, int>> pairs;
  for (const int v : source.spectral_samples()) pairs.emplace_back(v, forward[v]);
  return curvature_disagreement(source.smoothed_curvature(), target.smoothed_curvature(), pairs);
}

DenseEvidence measure_dense_map(const PreprocessedShape& source, const PreprocessedShape& target,
                                const std::vector<int>& forward, const std::vector<int>& reverse,
                                int distortion_sources, int threads) {
  DenseEvidence evidence;
  evidence.orientation =
      dense_orientation_agreement(source.mesh(), source.normals(), target.mesh(), target.normals(), forward);
  evidence.neighbourhood_orientation = neighbourhood_orientation_agreement(
      source.mesh(), source.normals(), source.geodesics().topology(), target.mesh(), target.normals(), forward,
      source.spectral_samples(), kNeighbourhoodRadius * source.diameter(), threads);
  evidence.signature_disagreement = heat_signature_disagreement(source, target, forward);
  evidence.curvature_disagreement = curvature_disagreement(source, target, forward);

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
      sums[a] += std::abs(source.sample_field(a, b) - d_target);
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

double choice_score(const DenseEvidence& evidence) {
  return evidence.curvature_disagreement * std::cbrt(evidence.distortion);
}

double mirror_threshold(double best_orientation, double orientation_margin) {
  return std::min(kMirrorOrientation, best_orientation - orientation_margin);
}

namespace {

// Whether a candidate sends every landmark within kLandmarkTolerance of its partner.
bool honours_landmarks(const DenseCandidate& candidate) { return candidate.landmark_error <= kLandmarkTolerance; }

}  // namespace

int choose_dense_candidate(std::vector<DenseCandidate>& candidates, double orientation_margin, std::string& why) {
  const bool some_honour = std::any_of(candidates.begin(), candidates.end(), honours_landmarks);
  // Candidates off the landmarks lose to any on them, so they take no part in the tests.
  auto competes = [&](const DenseCandidate& c) { return !some_honour || honours_landmarks(c); };
  double best_orientation = 0;
  for (const auto& c : candidates)
    if (competes(c)) best_orientation = std::max(best_orientation, c.evidence.orientation);
  const double threshold = mirror_threshold(best_orientation, orientation_margin);
  bool any_finished = false;
  for (DenseCandidate& c : candidates) {
    c.score = choice_score(c.evidence);
    c.mirrored = c.evidence.orientation < threshold;
    any_finished = any_finished || (competes(c) && !c.mirrored && c.finished);
  }
  int winner = -1;
  for (int i = 0; i < static_cast<int>(candidates.size()); ++i) {
    const DenseCandidate& c = candidates[i];
    if (!competes(c) || c.mirrored || (any_finished && !c.finished)) continue;
    if (winner < 0 || c.score < candidates[winner].score) winner = i;
  }
  const int landmark_losers = static_cast<int>(
      std::count_if(candidates.begin(), candidates.end(), [&](const DenseCandidate& c) { return !competes(c); }));
  char text[400];
  std::snprintf(text, sizeof text,
                "least curvature disagreement x cube root of distortion (%.6f) among the %d of %d refined "
                "candidates that keep the handedness of at least %.3f of the faces (best %.3f)%s%s",
                candidates[winner].score,
                static_cast<int>(std::count_if(candidates.begin(), candidates.end(),
                                               [&](const DenseCandidate& c) {
                                                 return competes(c) && !c.mirrored && (c.finished || !any_finished);
                                               })),
                static_cast<int>(candidates.size()), threshold, best_orientation,
                any_finished ? " and were finished" : "",
                landmark_losers > 0 ? (", " + std::to_string(landmark_losers) +
                                       " sending a landmark farther than the tolerance from its partner left out")
                                          .c_str()
                                    : (some_honour ? "" : ", none honouring the landmarks"));
  why = text;
  return winner;
}

}  // namespace isocorr
