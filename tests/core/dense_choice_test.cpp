// The choice by dense evidence: mirrors, turned bodies and swapped limbs lose to the right map.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/refinement/dense_choice.h"
#include "isocorr/refinement/refinement.h"
#include "isocorr/refinement/zoomout.h"
#include "refinement_fixtures.h"
#include "spectral_test_shapes.h"

namespace isocorr {
namespace {

using test_support::exact_and_near;
using test_support::spectral_options;

// An ellipsoid with three different axes has exactly one intrinsic mirror per axis plane;
// a map started from the x-mirror stays a mirror under refinement (it is an exact isometry),
// so the choice must drop it by its orientation, not by distortion.
TEST(DenseChoice, PrefersTheTrueMapToItsMirrorImage) {
  TriangleMesh ellipsoid = icosphere(4);
  for (Vec3& p : ellipsoid.vertices) p = Vec3(p.x() * 1.0, p.y() * 1.6, p.z() * 2.3);
  const RenumberedCopy copy = rotated_scaled_renumbered(ellipsoid, 1.0, 9);
  const auto source = PreprocessedShape::build(ellipsoid, spectral_options());
  const auto target = PreprocessedShape::build(copy.mesh, spectral_options());

  auto nearest_target_sample = [&](int vertex) {
    int best = 0;
    for (int j = 0; j < target->num_samples(); ++j)
      if ((copy.mesh.vertices[target->sample_vertex(j)] - copy.mesh.vertices[vertex]).squaredNorm() <
          (copy.mesh.vertices[target->sample_vertex(best)] - copy.mesh.vertices[vertex]).squaredNorm())
        best = j;
    return best;
  };
  // [0] the mirror, ranked first; [1] the true map; [2] the true map again, with a quarter
  // of its pairs credited to another target sample: distinct as tracked maps, the same
  // once refined, so refined and reported once.
  std::vector<TrackedMap> tracked(3);
  for (int i = 0; i < source->num_samples(); ++i) {
    const int v = source->sample_vertex(i);
    for (int which = 0; which < 3; ++which) {
      SamplePair pair;
      pair.source_sample = i;
      pair.target_vertex = copy.permutation[which == 0 ? test_support::x_mirror_of(ellipsoid, v) : v];
      pair.target_sample = nearest_target_sample(pair.target_vertex);
      if (which == 2 && i % 4 == 0) pair.target_sample = (pair.target_sample + 1) % target->num_samples();
      tracked[which].pairs.push_back(pair);
    }
  }
  MatchSettings settings;
  settings.zoomout.k_start = 10;
  settings.zoomout.k_end = 60;
  settings.threads = 2;
  const RefinedMatch refined = refine_and_choose(*source, *target, tracked, {0, 1, 2}, settings, {});
  // The screen refines the mirror last; the true map's copy is dropped once refined.
  ASSERT_EQ(refined.candidates.size(), 2u);
  EXPECT_EQ(refined.candidates[0].tracked_index, 1);
  EXPECT_EQ(refined.candidates[1].tracked_index, 0);
  EXPECT_TRUE(refined.candidates[1].mirrored);
  EXPECT_LT(refined.candidates[1].evidence.orientation, 0.1);
  EXPECT_GT(refined.candidates[0].evidence.orientation, 0.9);
  EXPECT_EQ(refined.candidates[refined.chosen].tracked_index, 1);
  const auto [exact, near] = exact_and_near(refined.dense.forward, copy.permutation, target->geodesics().topology());
  EXPECT_GE(near, 0.95);
}

// A finished refined candidate with the evidence the choice reads.
DenseCandidate candidate_with(double orientation, double curvature_disagreement, double distortion) {
  DenseCandidate c;
  c.evidence.orientation = orientation;
  c.evidence.curvature_disagreement = curvature_disagreement;
  c.evidence.distortion = distortion;
  return c;
}

TEST(DenseChoice, ATurnedMapLosesOnCurvature) {
  // Turned: keeps handedness, is as isometric between coarse samples and nearly as close
  // in heat signatures, but its points land where the surface is shaped differently.
  std::vector<DenseCandidate> candidates = {
      candidate_with(0.95, 0.19, 0.009),
      candidate_with(0.97, 0.14, 0.010),  // true
      candidate_with(0.05, 0.14, 0.010),  // mirror: as isometric, as similar, wrong hand
  };
  candidates[0].evidence.signature_disagreement = 0.0105;
  candidates[1].evidence.signature_disagreement = 0.0107;
  candidates[2].evidence.signature_disagreement = 0.0107;
  std::string why;
  EXPECT_EQ(choose_dense_candidate(candidates, 0.1, why), 1);
  EXPECT_TRUE(candidates[2].mirrored);
  EXPECT_FALSE(candidates[0].mirrored);
  EXPECT_NE(why.find("curvature"), std::string::npos);
}

// The user's landmarks outrank the evidence: a candidate that sends one far from its
// partner loses to any that does not, even to a worse-scoring one; and the mirror test is
// made among those that honour them. Without any that honours them, the evidence decides.
TEST(DenseChoice, ACandidateOffTheLandmarksLosesToOneOnThem) {
  std::vector<DenseCandidate> candidates = {
      candidate_with(0.97, 0.14, 0.010),  // the evidence's choice, a landmark on the wrong side
      candidate_with(0.95, 0.19, 0.009),  // turned the way the landmark says
      candidate_with(0.05, 0.10, 0.010),  // mirrored, though on the landmarks
  };
  candidates[0].landmark_error = 0.6;
  candidates[1].landmark_error = 0.02;
  candidates[2].landmark_error = 0.03;
  std::string why;
  EXPECT_EQ(choose_dense_candidate(candidates, 0.1, why), 1);
  EXPECT_TRUE(candidates[2].mirrored);
  EXPECT_NE(why.find("1 sending a landmark farther"), std::string::npos) << why;

  for (DenseCandidate& c : candidates) c.landmark_error = 0.5;
  EXPECT_EQ(choose_dense_candidate(candidates, 0.1, why), 0);
  EXPECT_NE(why.find("none honouring the landmarks"), std::string::npos) << why;
}

// A map with a swapped limb looks at the same shapes as the right map (curvature within
// 2%, SCAPE 002 -> 008) but tears geodesics at its seams; a turned body's distortion is as
// low as the right map's, its curvature is not.
TEST(DenseChoice, ASwappedLimbLosesOnDistortionATurnedBodyOnCurvature) {
  std::vector<DenseCandidate> candidates = {
      candidate_with(0.64, 0.1396, 0.0339),  // swapped limb
      candidate_with(0.76, 0.1643, 0.0273),  // turned
      candidate_with(0.93, 0.1415, 0.0302),  // right
  };
  std::string why;
  EXPECT_EQ(choose_dense_candidate(candidates, 0.1, why), 2);
  EXPECT_NE(why.find("distortion"), std::string::npos);
}

// A right map in a stretched pose can be more distorted than a turned body (SCAPE
// 003 -> 014: 29% more); its curvature agrees 11% better, and curvature outweighs
// distortion per cent for per cent. The plain product of the two chose the turned body.
TEST(DenseChoice, ARightMapMoreDistortedThanATurnedBodyWinsOnCurvature) {
  std::vector<DenseCandidate> candidates = {
      candidate_with(0.78, 0.1612, 0.0253),  // turned
      candidate_with(0.77, 0.1450, 0.0326),  // right
  };
  std::string why;
  EXPECT_EQ(choose_dense_candidate(candidates, 0.1, why), 1);
  EXPECT_LT(candidates[0].evidence.curvature_disagreement * candidates[0].evidence.distortion,
            candidates[1].evidence.curvature_disagreement * candidates[1].evidence.distortion);
  EXPECT_DOUBLE_EQ(candidates[1].score, choice_score(candidates[1].evidence));
}

// A right map with a few misplaced regions keeps fewer faces' handedness than a clean
// turned body; it is still no mirror, and it wins on curvature. Only when no candidate
// keeps most faces does the relative margin decide.
TEST(DenseChoice, ARightMapWithLowerHandednessIsNoMirror) {
  std::vector<DenseCandidate> candidates = {
      candidate_with(0.82, 0.13, 0.03),  // turned
      candidate_with(0.61, 0.06, 0.03),  // right, partly misplaced
  };
  std::string why;
  EXPECT_EQ(choose_dense_candidate(candidates, 0.1, why), 1);
  EXPECT_FALSE(candidates[1].mirrored);
  EXPECT_DOUBLE_EQ(mirror_threshold(0.82, 0.1), kMirrorOrientation);
  EXPECT_DOUBLE_EQ(mirror_threshold(0.45, 0.1), 0.35);
}

// A raw spectral map is no match for a finished one (refinement.h): it competes only when
// no finished candidate is eligible.
TEST(DenseChoice, AnUnfinishedCandidateCompetesOnlyWhenNoFinishedOneIsEligible) {
  std::vector<DenseCandidate> candidates = {
      candidate_with(0.9, 0.13, 0.03),
      candidate_with(0.75, 0.12, 0.03),  // raw: lower curvature
      candidate_with(0.1, 0.11, 0.03),   // a finished mirror
  };
  candidates[1].finished = false;
  std::string why;
  EXPECT_EQ(choose_dense_candidate(candidates, 0.1, why), 0);
  candidates[0].evidence.orientation = 0.2;
  EXPECT_EQ(choose_dense_candidate(candidates, 0.1, why), 1);
}

// On an asymmetric shape, the true map of a rotated, scaled, renumbered copy has (up to
// the copy's float rounding) the same signatures at both ends; a map that sends each point
// to where another point goes does not.
TEST(DenseChoice, HeatSignaturesAgreeAlongTheTrueMapOnly) {
  const TriangleMesh blob = limbed_blob(4);
  const RenumberedCopy copy = rotated_scaled_renumbered(blob, 1.7, 5);
  const auto source = PreprocessedShape::build(blob, spectral_options());
  const auto target = PreprocessedShape::build(copy.mesh, spectral_options());
  const double along_truth = heat_signature_disagreement(*source, *target, copy.permutation);
  EXPECT_LT(along_truth, 1e-3);

  const int n = blob.num_vertices();
  std::vector<int> shifted(n);
  for (int v = 0; v < n; ++v) shifted[v] = copy.permutation[(static_cast<long long>(v) * 7919 + 13) % n];
  EXPECT_GT(heat_signature_disagreement(*source, *target, shifted), 10 * along_truth + 0.01);
}

}  // namespace
}  // namespace isocorr
