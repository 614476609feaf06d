// The creature and a rotated, scaled, renumbered copy of it, preprocessed, with the true map
// between them: a pair whose every correspondence is known, for the matching stages' tests.
#pragma once

#include <memory>
#include <vector>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr::testing {

struct CreaturePair {
  std::shared_ptr<const PreprocessedShape> source, target;
  std::vector<int> truth;  // clean source vertex -> its clean target vertex

  explicit CreaturePair(int subdivisions, double scale = 1.7, uint32_t seed = 5) {
    const TriangleMesh creature = limbed_blob(subdivisions);
    const RenumberedCopy copy = rotated_scaled_renumbered(creature, scale, seed);
    source = PreprocessedShape::build(creature, PreprocessOptions{});
    target = PreprocessedShape::build(copy.mesh, PreprocessOptions{});
    truth.resize(source->mesh().num_vertices());
    for (int v = 0; v < static_cast<int>(truth.size()); ++v)
      truth[v] = target->clean().input_to_clean[copy.permutation[source->clean().clean_to_input[v]]];
  }

  // Geodesic distance on the target from `image` to the true image of source vertex `v`, as a
  // fraction of the target's diameter.
  double error(int v, int image) const {
    FastMarching::Workspace workspace;
    return target->geodesics().distance_between(truth[v], image, workspace) / target->diameter();
  }

  // The target level-0 sample nearest the true image of source sample `i`.
  int true_target_sample(int i, int target_samples) const {
    const int image = truth[source->sample_vertex(i)];
    int best = 0;
    for (int j = 1; j < target_samples; ++j)
      if (target->field(j, image) < target->field(best, image)) best = j;
    return best;
  }
};

}  // namespace isocorr::testing
