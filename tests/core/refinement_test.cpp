// Spectral refinement and the choice by dense evidence on shapes with known answers.
#include <gtest/gtest.h>

#include <random>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/refinement/refinement.h"
#include "isocorr/refinement/zoomout.h"

namespace isocorr {
namespace {

PreprocessOptions spectral_options() {
  PreprocessOptions options;
  options.spectral_basis = 60;
  options.spectral_samples = 800;
  options.threads = 2;
  return options;
}

SpectralSide side_of(const PreprocessedShape& shape) {
  return {&shape.spectral_basis(), &shape.geodesics().topology(), &shape.spectral_samples(),
          &shape.spectral_eigenvalues()};
}

// Fraction of `image` equal to `truth`, and of the rest within one ring of it.
std::pair<double, double> exact_and_near(const std::vector<int>& image, const std::vector<int>& truth,
                                         const MeshTopology& topology) {
  int exact = 0, near = 0;
  for (size_t v = 0; v < image.size(); ++v) {
    if (image[v] == truth[v]) {
      ++exact;
      continue;
    }
    for (const int* w = topology.neighbours_begin(truth[v]); w != topology.neighbours_end(truth[v]); ++w)
      near += *w == image[v];
  }
  return {static_cast<double>(exact) / image.size(), static_cast<double>(exact + near) / image.size()};
}

TEST(ZoomOut, RecoversAPermutedRotatedCopyFromANoisyStart) {
  const TriangleMesh blob = limbed_blob(4);
  const RenumberedCopy copy = rotated_scaled_renumbered(blob, 1.7, 5);
  const auto source = PreprocessedShape::build(blob, spectral_options());
  const auto target = PreprocessedShape::build(copy.mesh, spectral_options());
  // clean_mesh keeps the numbering of these closed, clean meshes.
  ASSERT_EQ(source->mesh().num_vertices(), blob.num_vertices());

  // 300 true pairs, a quarter of them replaced by random target vertices.
  std::mt19937 random(3);
  std::uniform_int_distribution<int> any_vertex(0, blob.num_vertices() - 1);
  std::vector<std::pair<int, int>> start;
  for (int i = 0; i < 300; ++i) {
    const int v = any_vertex(random);
    start.emplace_back(v, i % 4 == 0 ? any_vertex(random) : copy.permutation[v]);
  }
  std::vector<int> inverse(copy.permutation.size());
  for (size_t v = 0; v < inverse.size(); ++v) inverse[copy.permutation[v]] = static_cast<int>(v);
  for (const double commutativity : {0.0, 10.0}) {
    SCOPED_TRACE(commutativity);
    ZoomOutOptions options;
    options.k_start = 10;
    options.k_end = 60;
    options.commutativity = commutativity;
    const SpectralMap map = zoomout(side_of(*source), side_of(*target), start, options);

    const auto [exact, near] = exact_and_near(map.image, copy.permutation, target->geodesics().topology());
    EXPECT_GE(exact, 0.99);
    EXPECT_GE(near, 0.999);
    const auto [reverse_exact, reverse_near] =
        exact_and_near(map.reverse_image, inverse, source->geodesics().topology());
    EXPECT_GE(reverse_exact, 0.99);
    EXPECT_GE(reverse_near, 0.999);
  }
}

// An ellipsoid with three different axes has exactly one intrinsic mirror per axis plane;
// a map started from the x-mirror stays a mirror under refinement (it is an exact isometry),
// so the choice must drop it by its orientation, not by distortion.
TEST(DenseChoice, PrefersTheTrueMapToItsMirrorImage) {
  TriangleMesh ellipsoid = icosphere(4);
  for (Vec3& p : ellipsoid.vertices) p = Vec3(p.x() * 1.0, p.y() * 1.6, p.z() * 2.3);
  const RenumberedCopy copy = rotated_scaled_renumbered(ellipsoid, 1.0, 9);
  const auto source = PreprocessedShape::build(ellipsoid, spectral_options());
  const auto target = PreprocessedShape::build(copy.mesh, spectral_options());

  auto mirror_of = [&](int v) {
    const Vec3 reflected(-ellipsoid.vertices[v].x(), ellipsoid.vertices[v].y(), ellipsoid.vertices[v].z());
    int best = 0;
    for (int w = 0; w < ellipsoid.num_vertices(); ++w)
      if ((ellipsoid.vertices[w] - reflected).squaredNorm() < (ellipsoid.vertices[best] - reflected).squaredNorm())
        best = w;
    return best;
  };
  auto nearest_target_sample = [&](int vertex) {
    int best = 0;
    for (int j = 0; j < target->num_samples(); ++j)
      if ((copy.mesh.vertices[target->sample_vertex(j)] - copy.mesh.vertices[vertex]).squaredNorm() <
          (copy.mesh.vertices[target->sample_vertex(best)] - copy.mesh.vertices[vertex]).squaredNorm())
        best = j;
    return best;
  };
  std::vector<TrackedMap> tracked(2);  // [0] the mirror, ranked first; [1] the true map
  for (int i = 0; i < source->num_samples(); ++i) {
    const int v = source->sample_vertex(i);
    for (int which = 0; which < 2; ++which) {
      SamplePair pair;
      pair.source_sample = i;
      pair.target_vertex = copy.permutation[which == 0 ? mirror_of(v) : v];
      pair.target_sample = nearest_target_sample(pair.target_vertex);
      tracked[which].pairs.push_back(pair);
    }
  }
  MatchSettings settings;
  settings.zoomout.k_start = 10;
  settings.zoomout.k_end = 60;
  settings.threads = 2;
  const RefinedMatch refined = refine_and_choose(*source, *target, tracked, {0, 1}, settings, {});
  ASSERT_EQ(refined.candidates.size(), 2u);
  EXPECT_TRUE(refined.candidates[0].mirrored);
  EXPECT_LT(refined.candidates[0].evidence.orientation, 0.1);
  EXPECT_GT(refined.candidates[1].evidence.orientation, 0.9);
  EXPECT_EQ(refined.candidates[refined.chosen].tracked_index, 1);
  const auto [exact, near] = exact_and_near(refined.dense.forward, copy.permutation, target->geodesics().topology());
  EXPECT_GE(near, 0.95);
}

TEST(DenseChoice, ATurnedMapLosesOnDistortionAndRoundTrip) {
  std::vector<DenseCandidate> candidates(3);
  candidates[0].evidence = {0.95, 0.06, 0.07, 0.05};  // turned: keeps handedness, stretches
  candidates[1].evidence = {0.97, 0.01, 0.02, 0.005};  // true
  candidates[2].evidence = {0.05, 0.01, 0.03, 0.005};  // mirror: as isometric, wrong hand
  std::string why;
  EXPECT_EQ(choose_dense_candidate(candidates, 0.1, why), 1);
  EXPECT_TRUE(candidates[2].mirrored);
  EXPECT_FALSE(candidates[0].mirrored);
  EXPECT_FALSE(why.empty());
}

}  // namespace
}  // namespace isocorr
