// The refinement from sparse pairs and from a map's own images, on an isometric copy.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/refinement/refinement.h"
#include "refinement_fixtures.h"
#include "spectral_test_shapes.h"

namespace isocorr {
namespace {

using test_support::exact_and_near;
using test_support::spectral_options;

// A limbed blob and a rotated, scaled, renumbered copy, with the settings both refinements
// below run at (a small basis: the blob is small).
struct IsometricCopy {
  TriangleMesh blob = limbed_blob(4);
  RenumberedCopy copy = rotated_scaled_renumbered(blob, 1.7, 5);
  MatchSettings settings = small_basis_settings();
  std::shared_ptr<const PreprocessedShape> source = PreprocessedShape::build(blob, settings.preprocess);
  std::shared_ptr<const PreprocessedShape> target = PreprocessedShape::build(copy.mesh, settings.preprocess);
  std::vector<int> inverse = inverse_of(copy.permutation);

  static MatchSettings small_basis_settings() {
    MatchSettings settings;
    settings.preprocess = spectral_options();
    settings.threads = 2;
    settings.zoomout.k_start = 10;
    settings.zoomout.k_end = 60;
    return settings;
  }
  static std::vector<int> inverse_of(const std::vector<int>& permutation) {
    std::vector<int> inverse(permutation.size());
    for (size_t v = 0; v < inverse.size(); ++v) inverse[permutation[v]] = static_cast<int>(v);
    return inverse;
  }
  // At least 99% of the vertices of each shape mapped exactly, both ways.
  void expect_true_map(const SpectralMap& map) const {
    EXPECT_GE(exact_and_near(map.image, copy.permutation, target->geodesics().topology()).first, 0.99);
    EXPECT_GE(exact_and_near(map.reverse_image, inverse, source->geodesics().topology()).first, 0.99);
  }
};

// The refinement alone, from a few hundred true pairs of a rotated, scaled, renumbered copy
// (what isocorr-bench --from-truth runs): every vertex comes back to its true image, both ways.
TEST(RefineFromPairs, MapsEveryVertexOfAnIsometricCopyFromSparseTruePairs) {
  const IsometricCopy pair;
  std::mt19937 random(7);
  std::uniform_int_distribution<int> any_vertex(0, pair.blob.num_vertices() - 1);
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < 200; ++i) {
    const int v = any_vertex(random);
    pairs.emplace_back(v, pair.copy.permutation[v]);
  }
  const SpectralMap map = refine_from_pairs(*pair.source, *pair.target, pairs, pair.settings);
  pair.expect_true_map(map);
  ASSERT_EQ(map.residual.size(), map.image.size());
  EXPECT_LT(*std::max_element(map.residual.begin(), map.residual.end()), 0.01);
}

// A further pass from a refined map's own images: a map with a fifth of its images one ring
// off (a slide's local picture) comes back to the true map, both ways.
TEST(RefineAgain, PullsANoisyMapOfAnIsometricCopyBackToTheTruth) {
  const IsometricCopy pair;
  const MeshTopology& target_topology = pair.target->geodesics().topology();
  SpectralMap noisy;
  noisy.image = pair.copy.permutation;
  std::mt19937 random(13);
  for (int& w : noisy.image)
    if (random() % 5 == 0) w = *target_topology.neighbours_begin(w);
  ASSERT_LT(exact_and_near(noisy.image, pair.copy.permutation, target_topology).first, 0.85);
  pair.expect_true_map(refine_again(*pair.source, *pair.target, noisy, pair.settings));
}

}  // namespace
}  // namespace isocorr
