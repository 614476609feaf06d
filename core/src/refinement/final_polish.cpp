#include "isocorr/refinement/final_polish.h"

#include "isocorr/refinement/dense_choice.h"
#include "isocorr/refinement/rigidity_polish.h"

namespace isocorr {

FinalPolishOutcome extend_rigidity_polish(const PreprocessedShape& source, const PreprocessedShape& target,
                                          int iterations, int threads, SpectralMap& map,
                                          const JobControl& control) {
  FinalPolishOutcome outcome;
  if (iterations <= 0) return outcome;
  RigidityOptions options;
  options.iterations = iterations;
  SpectralMap longer = map;
  RigidityPolish(source, target, options).apply(longer, control.with_threads(threads));
  outcome.curvature_before = curvature_disagreement(source, target, map.image);
  outcome.curvature_after = curvature_disagreement(source, target, longer.image);
  outcome.kept = outcome.curvature_after < outcome.curvature_before;
  if (outcome.kept) map = std::move(longer);
  return outcome;
}

}  // namespace isocorr
