// The sampled stage of ZoomOut stopped and continued, and the screening of tracked maps by it.
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <set>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/refinement/candidate_screening.h"
#include "isocorr/refinement/refinement.h"
#include "isocorr/sampling/vertex_spreading.h"
#include "spectral_test_shapes.h"

namespace isocorr {
namespace {

using test_support::spectral_options;

ZoomOutOptions zoomout_options() {
  ZoomOutOptions options;
  options.k_start = 10;
  options.k_end = 60;
  return options;
}

struct BlobPair {
  TriangleMesh blob = limbed_blob(4);
  RenumberedCopy copy = rotated_scaled_renumbered(blob, 1.7, 5);
  std::shared_ptr<const PreprocessedShape> source = PreprocessedShape::build(blob, spectral_options());
  std::shared_ptr<const PreprocessedShape> target = PreprocessedShape::build(copy.mesh, spectral_options());
};

// 300 pairs of the true map, every fourth replaced by a random target vertex.
std::vector<std::pair<int, int>> noisy_true_start(const BlobPair& pair) {
  std::mt19937 random(3);
  std::uniform_int_distribution<int> any_vertex(0, pair.blob.num_vertices() - 1);
  std::vector<std::pair<int, int>> start;
  for (int i = 0; i < 300; ++i) {
    const int v = any_vertex(random);
    start.emplace_back(v, i % 4 == 0 ? any_vertex(random) : pair.copy.permutation[v]);
  }
  return start;
}

double share_exact(const std::vector<int>& image, const std::vector<int>& truth) {
  int exact = 0;
  for (size_t v = 0; v < image.size(); ++v) exact += image[v] == truth[v];
  return static_cast<double>(exact) / image.size();
}

TEST(ZoomOut, ContinuingOnSamplesIsTheSameAsGrowingAtOnce) {
  const BlobPair pair;
  const SpectralSide source = spectral_side(*pair.source), target = spectral_side(*pair.target);
  const auto start = noisy_true_start(pair);
  const SampleMap at_once = zoomout_on_samples(source, target, start, 60, zoomout_options());
  SampleMap in_two = zoomout_on_samples(source, target, start, 30, zoomout_options());
  EXPECT_EQ(in_two.c.rows(), 30);
  continue_on_samples(source, target, 60, zoomout_options(), in_two);
  EXPECT_EQ(at_once.c.rows(), 60);
  EXPECT_EQ(in_two.images, at_once.images);
  EXPECT_TRUE(in_two.c.isApprox(at_once.c));
}

TEST(ZoomOut, ContinuesAMapGrownOnFewerSamples) {
  const BlobPair pair;
  const SpectralSide source = spectral_side(*pair.source), target = spectral_side(*pair.target);
  const std::vector<int> few_source(pair.source->spectral_samples().begin(),
                                    pair.source->spectral_samples().begin() + 150);
  const std::vector<int> few_target(pair.target->spectral_samples().begin(),
                                    pair.target->spectral_samples().begin() + 150);
  SpectralSide coarse_source = source, coarse_target = target;
  coarse_source.samples = &few_source;
  coarse_target.samples = &few_target;
  SampleMap map = zoomout_on_samples(coarse_source, coarse_target, noisy_true_start(pair), 30, zoomout_options());
  ASSERT_EQ(map.images.size(), 150u);
  continue_on_samples(source, target, 60, zoomout_options(), map);
  ASSERT_EQ(map.images.size(), pair.source->spectral_samples().size());
  const SpectralMap dense = zoomout_dense(source, target, map, zoomout_options());
  EXPECT_GE(share_exact(dense.image, pair.copy.permutation), 0.99);
}

TEST(CandidateScreening, SpreadSampleMapSendsEachVertexWhereItsNearestSampleGoes) {
  const BlobPair pair;
  const std::vector<int>& samples = pair.source->spectral_samples();
  std::vector<int> images(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) images[i] = pair.copy.permutation[samples[i]];
  const std::vector<int> spread = spread_sample_map(
      nearest_centre(pair.source->geodesics().topology(), pair.blob.num_vertices(), samples), images);
  ASSERT_EQ(spread.size(), static_cast<size_t>(pair.blob.num_vertices()));
  for (size_t i = 0; i < samples.size(); ++i) EXPECT_EQ(spread[samples[i]], images[i]);
  const std::set<int> sample_images(images.begin(), images.end());
  for (const int image : spread) EXPECT_TRUE(sample_images.count(image));
}

// Shifted along the vertex numbering: a map that sends every point where another goes.
std::vector<int> scrambled(const BlobPair& pair, long long stride) {
  const int n = pair.blob.num_vertices();
  std::vector<int> image(n);
  for (int v = 0; v < n; ++v) image[v] = pair.copy.permutation[(static_cast<long long>(v) * stride + 13) % n];
  return image;
}

// A tracked map from a vertex map: each source sample's image and the target sample
// nearest to it (which tells tracked maps apart).
TrackedMap tracked_from(const PreprocessedShape& source, const PreprocessedShape& target,
                        const std::vector<int>& target_of_vertex) {
  TrackedMap map;
  for (int i = 0; i < source.num_samples(); ++i) {
    SamplePair p;
    p.source_sample = i;
    p.target_vertex = target_of_vertex[source.sample_vertex(i)];
    const Vec3& image = target.mesh().vertices[p.target_vertex];
    for (int j = 1; j < target.num_samples(); ++j)
      if ((target.mesh().vertices[target.sample_vertex(j)] - image).squaredNorm() <
          (target.mesh().vertices[target.sample_vertex(p.target_sample)] - image).squaredNorm())
        p.target_sample = j;
    map.pairs.push_back(p);
  }
  return map;
}

// On an asymmetric shape a start that sends every point where another point goes stays
// far from the shapes' curvature; the true start agrees and keeps handedness.
TEST(CandidateScreening, TheTrueStartAgreesInCurvatureAndHandedness) {
  const BlobPair pair;
  const std::vector<TrackedMap> tracked = {tracked_from(*pair.source, *pair.target, scrambled(pair, 7919)),
                                           tracked_from(*pair.source, *pair.target, pair.copy.permutation)};
  const auto screened = screen_tracked_maps(*pair.source, *pair.target, tracked, {0, 1}, 30, zoomout_options());
  ASSERT_EQ(screened.size(), 2u);
  EXPECT_EQ(screened[0].evidence.tracked_index, 0);
  EXPECT_EQ(screened[0].sampled.c.rows(), 30);
  EXPECT_GT(screened[1].evidence.orientation, 0.95);
  EXPECT_LT(screened[1].evidence.curvature, 0.02);
  EXPECT_GT(screened[0].evidence.curvature, 5 * screened[1].evidence.curvature + 0.05);
}

// Refinement screens before it refines: of two scrambled starts ranked first and the true
// one last, the true one is refined first when two may be, and wins.
TEST(CandidateScreening, TheTrueStartRankedLastIsRefinedFirst) {
  const BlobPair pair;
  const std::vector<TrackedMap> tracked = {tracked_from(*pair.source, *pair.target, scrambled(pair, 7919)),
                                           tracked_from(*pair.source, *pair.target, scrambled(pair, 104729)),
                                           tracked_from(*pair.source, *pair.target, pair.copy.permutation)};
  MatchSettings settings;
  settings.zoomout.k_start = 10;
  settings.zoomout.k_end = 60;
  settings.screen_k_end = 30;
  settings.refine_candidates = 2;
  settings.threads = 2;
  const RefinedMatch refined = refine_and_choose(*pair.source, *pair.target, tracked, {0, 1, 2}, settings, {});
  ASSERT_EQ(refined.screened.size(), 3u);
  EXPECT_EQ(refined.screened[0].tracked_index, 0);
  ASSERT_EQ(refined.candidates.size(), 2u);
  EXPECT_EQ(refined.candidates[0].tracked_index, 2);
  EXPECT_EQ(refined.candidates[refined.chosen].tracked_index, 2);
  EXPECT_GE(share_exact(refined.dense.forward, pair.copy.permutation), 0.95);
}

TEST(CandidateScreening, StartsAlternateBetweenTheTrackedRankingAndTheScreen) {
  const BlobPair pair;
  std::vector<ScreenedStart> screened(5);
  const double orientation[] = {0.2, 0.8, 0.7, 0.75, 0.9}, curvature[] = {0.05, 0.2, 0.1, 0.1, 0.3};
  for (int i = 0; i < 5; ++i) {
    screened[i].evidence.tracked_index = i;
    screened[i].evidence.orientation = orientation[i];
    screened[i].evidence.curvature = curvature[i];
  }
  // Ranking: 0 (mirrored: skipped), 1, 2, 3, 4; screen: 2, 3 (a tie keeps the ranking), 1, 4, 0.
  const auto picked = starts_to_refine(screened, 3, 0.1, pair.target->geodesics().topology());
  ASSERT_EQ(picked.size(), 3u);
  EXPECT_EQ(picked[0].evidence.tracked_index, 2);
  EXPECT_EQ(picked[1].evidence.tracked_index, 1);
  EXPECT_EQ(picked[2].evidence.tracked_index, 3);
  // With room for all, the mirror comes last.
  const auto all = starts_to_refine(screened, 10, 0.1, pair.target->geodesics().topology());
  ASSERT_EQ(all.size(), 5u);
  EXPECT_EQ(all[4].evidence.tracked_index, 0);
}

TEST(CandidateScreening, AStartThatConvergedWhereAnEarlierPickDidIsSkipped) {
  const BlobPair pair;
  std::vector<ScreenedStart> screened(4);
  const double curvature[] = {0.3, 0.1, 0.2, 0.4};
  for (int i = 0; i < 4; ++i) {
    screened[i].evidence.tracked_index = i;
    screened[i].evidence.orientation = 0.9;
    screened[i].evidence.curvature = curvature[i];
    screened[i].sampled.images = {i, 1000 + i, 2000 + i};
  }
  screened[2].sampled.images = screened[0].sampled.images;
  // Ranking 0, 1, 2, 3; screen 1, 2, 0, 3; 2 ends where 0 did.
  const auto picked = starts_to_refine(screened, 3, 0.1, pair.target->geodesics().topology());
  ASSERT_EQ(picked.size(), 3u);
  EXPECT_EQ(picked[0].evidence.tracked_index, 0);
  EXPECT_EQ(picked[1].evidence.tracked_index, 1);
  EXPECT_EQ(picked[2].evidence.tracked_index, 3);
}

}  // namespace
}  // namespace isocorr
