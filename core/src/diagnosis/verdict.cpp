#include "isocorr/diagnosis/verdict.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

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
  if (refinement.candidates.size() < 2) return;
  const DenseCandidate& chosen = refinement.candidates[refinement.chosen];
  if (chosen.score <= 0) return;
  int closest = -1;
  double closest_margin = 0, closest_separation = 0;
  for (int i = 0; i < static_cast<int>(refinement.candidates.size()); ++i) {
    const DenseCandidate& c = refinement.candidates[i];
    if (i == refinement.chosen || c.mirrored || c.landmark_error > kLandmarkTolerance) continue;
    const double margin = c.score / chosen.score - 1;
    if (margin >= kCloseCompetitorMargin || (closest >= 0 && margin >= closest_margin)) continue;
    const double separation = map_separation(source, target, c.forward, chosen.forward);
    if (separation < kDistinctMapSeparation) continue;
    closest = i, closest_margin = margin, closest_separation = separation;
  }
  if (closest < 0) return;
  const DenseCandidate& c = refinement.candidates[closest];
  verdict.reasons.push_back(
      sentence("a different map (refined candidate %d, %.2f of the diameter away on average, keeping the handedness "
               "of %.2f of the faces against the chosen map's %.2f) scored within %.1f%% of the chosen one: the choice "
               "was a near tie",
               closest, closest_separation, c.evidence.orientation, chosen.evidence.orientation,
               100 * std::max(0.0, closest_margin)));
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
    float largest = 0;
    for (int i = 0; i < target.num_samples(); ++i)
      largest = std::max(largest, std::abs(target.field(i, x) - target.field(i, y)));
    sum += largest;
  }
  return sum / samples.size();
}

MatchVerdict diagnose(const PreprocessedShape& source, const PreprocessedShape& target, const MatchResult& result) {
  MatchVerdict verdict;
  check_competitors(source, target, result.diagnostics.refinement, verdict);
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
