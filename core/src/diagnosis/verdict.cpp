#include "isocorr/diagnosis/verdict.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "isocorr/diagnosis/map_tearing.h"
#include "isocorr/refinement/dense_choice.h"
#include "isocorr/transfer/landmarks.h"

namespace isocorr {
namespace {

template <class... Args>
std::string sentence(const char* format, Args... args) {
  char text[300];
  std::snprintf(text, sizeof text, format, args...);
  return text;
}

// The closest distinct competitor of the chosen refined candidate, if any is close.
void check_competitors(const PreprocessedShape& source, const PreprocessedShape& target,
                       const RefinementDiagnostics& refinement, MatchVerdict& verdict) {
  const std::vector<int> close = close_competitors(source, target, refinement.candidates, refinement.chosen);
  if (close.empty()) return;
  const DenseCandidate& chosen = refinement.candidates[refinement.chosen];
  const DenseCandidate& c = refinement.candidates[close.front()];
  const double margin = c.score / chosen.score - 1;
  verdict.reasons.push_back(sentence(
      "a different map (refined candidate %d, %.2f of the diameter away on average, keeping the handedness of %.2f of "
      "the faces against the chosen map's %.2f) scored %.1f%% %s the chosen one: the choice was a near tie%s",
      close.front(), map_separation(source, target, c.forward, chosen.forward), c.evidence.orientation,
      chosen.evidence.orientation, 100 * std::abs(margin), margin >= 0 ? "above" : "below",
      chosen.reverse_score > 0 ? ", decided by both directions' evidence" : ""));
}

// A map that tears the surface in more places than right maps do.
void check_tearing(const MatchQuality& quality, MatchVerdict& verdict) {
  if (quality.torn_share <= kTornShare) return;
  verdict.reasons.push_back(sentence(
      "the map tears the surface: %.1f%% of the pairs of neighbouring samples land more than %.1f times as far apart "
      "(right maps stay under %.1f%%): a region may be mapped to the wrong place",
      100 * quality.torn_share, kTearStretch, 100 * kTornShare));
}

}  // namespace

double map_separation(const PreprocessedShape& source, const PreprocessedShape& target, const std::vector<int>& a,
                      const std::vector<int>& b) {
  const std::vector<int>& samples = source.spectral_samples();
  if (samples.empty() || target.num_samples() == 0) return 0;
  double sum = 0;
  for (const int s : samples) {
    const int x = a[s], y = b[s];
    if (x < 0 || y < 0 || x == y) continue;
    sum += sample_field_distance_bound(target, x, y);
  }
  return sum / samples.size();
}

std::vector<int> close_competitors(const PreprocessedShape& source, const PreprocessedShape& target,
                                   const std::vector<DenseCandidate>& candidates, int chosen) {
  std::vector<std::pair<double, int>> close;
  if (chosen < 0 || chosen >= static_cast<int>(candidates.size()) || candidates[chosen].score <= 0) return {};
  const DenseCandidate& winner = candidates[chosen];
  for (int i = 0; i < static_cast<int>(candidates.size()); ++i) {
    const DenseCandidate& c = candidates[i];
    if (i == chosen || c.mirrored || c.landmark_error > kLandmarkTolerance) continue;
    const double margin = c.score / winner.score - 1;
    if (margin >= kCloseCompetitorMargin) continue;
    if (map_separation(source, target, c.forward, winner.forward) < kDistinctMapSeparation) continue;
    close.push_back({margin, i});
  }
  std::sort(close.begin(), close.end());
  std::vector<int> indices;
  for (const auto& [margin, i] : close) indices.push_back(i);
  return indices;
}

MatchVerdict diagnose(const PreprocessedShape& source, const PreprocessedShape& target, const MatchResult& result) {
  MatchVerdict verdict;
  check_competitors(source, target, result.diagnostics.refinement, verdict);
  check_tearing(result.quality, verdict);
  if (result.quality.orientation < kMirrorOrientation)
    verdict.reasons.push_back(sentence("the map keeps the handedness of only %.2f of the faces: it may be a mirror image",
                                       result.quality.orientation));
  const LandmarkDiagnostics& landmarks = result.diagnostics.landmarks;
  if (landmarks.count > 0 && !landmarks.honoured)
    verdict.reasons.push_back("the chosen map did not honour the landmarks before they were pinned");
  verdict.suspect = !verdict.reasons.empty();
  return verdict;
}

}  // namespace isocorr
