// The verdict on a result: a near tie between two different maps, a map that reverses
// handedness, a map that tears the surface and landmarks left unhonoured make it suspect; a
// clear choice does not.
#include "isocorr/diagnosis/verdict.h"

#include <gtest/gtest.h>

#include "isocorr/diagnosis/map_tearing.h"
#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/refinement/dense_choice.h"
#include "spectral_test_shapes.h"

namespace isocorr {
namespace {

// An ellipsoid with three different axes and its rotated, renumbered copy; the true map and
// its mirror through the x = 0 plane, both in the shapes' clean numbering.
class VerdictOnEllipsoid : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    TriangleMesh ellipsoid = icosphere(4);
    for (Vec3& p : ellipsoid.vertices) p = Vec3(p.x() * 1.0, p.y() * 1.6, p.z() * 2.3);
    const RenumberedCopy copy = rotated_scaled_renumbered(ellipsoid, 1.0, 9);
    source_ = PreprocessedShape::build(ellipsoid, test_support::spectral_options());
    target_ = PreprocessedShape::build(copy.mesh, test_support::spectral_options());
    const CleanMesh& s = source_->clean();
    const CleanMesh& t = target_->clean();
    for (int c = 0; c < s.mesh.num_vertices(); ++c) {
      const int v = s.clean_to_input[c];
      truth_.push_back(t.input_to_clean[copy.permutation[v]]);
      mirror_.push_back(t.input_to_clean[copy.permutation[test_support::x_mirror_of(ellipsoid, v)]]);
    }
  }
  static void TearDownTestSuite() {
    source_.reset();
    target_.reset();
  }

  // A result whose refinement chose the true map (score 1) over one other candidate.
  static MatchResult chosen_over(const std::vector<int>& other, double other_score) {
    MatchResult result;
    DenseCandidate chosen, competitor;
    chosen.forward = truth_;
    chosen.score = 1;
    chosen.evidence.orientation = 0.9;
    competitor.forward = other;
    competitor.score = other_score;
    competitor.evidence.orientation = 0.8;
    result.diagnostics.refinement.candidates = {chosen, competitor};
    result.diagnostics.refinement.chosen = 0;
    result.quality.orientation = 0.9;
    return result;
  }

  static inline std::shared_ptr<const PreprocessedShape> source_, target_;
  static inline std::vector<int> truth_, mirror_;
};

TEST_F(VerdictOnEllipsoid, SeparationIsZeroForOneMapAndLargeForItsMirror) {
  EXPECT_EQ(map_separation(*source_, *target_, truth_, truth_), 0);
  EXPECT_GT(map_separation(*source_, *target_, truth_, mirror_), 3 * kDistinctMapSeparation);
}

TEST_F(VerdictOnEllipsoid, ANearTieWithADifferentMapIsSuspect) {
  const MatchVerdict tie = diagnose(*source_, *target_, chosen_over(mirror_, 1.02));
  EXPECT_TRUE(tie.suspect);
  ASSERT_EQ(tie.reasons.size(), 1u);
  EXPECT_NE(tie.reasons[0].find("scored 2.0% above the chosen one"), std::string::npos) << tie.reasons[0];
  EXPECT_STREQ(tie.status(), "suspect");

  const MatchVerdict clear = diagnose(*source_, *target_, chosen_over(mirror_, 1.2));
  EXPECT_FALSE(clear.suspect);
  EXPECT_STREQ(clear.status(), "ok");
  EXPECT_TRUE(clear.reasons.empty());
  // The same map refined twice is no competitor, however close its score.
  EXPECT_FALSE(diagnose(*source_, *target_, chosen_over(truth_, 1.01)).suspect);
}

TEST_F(VerdictOnEllipsoid, ReversedHandednessAndUnhonouredLandmarksAreSuspect) {
  MatchResult mirrored = chosen_over(mirror_, 1.5);
  mirrored.quality.orientation = 0.1;
  const MatchVerdict mirror = diagnose(*source_, *target_, mirrored);
  EXPECT_TRUE(mirror.suspect);
  ASSERT_EQ(mirror.reasons.size(), 1u);
  EXPECT_NE(mirror.reasons[0].find("mirror image"), std::string::npos);

  MatchResult off = chosen_over(mirror_, 1.5);
  off.diagnostics.landmarks.count = 2;
  off.diagnostics.landmarks.honoured = false;
  const MatchVerdict landmarks = diagnose(*source_, *target_, off);
  EXPECT_TRUE(landmarks.suspect);
  EXPECT_NE(landmarks.reasons.at(0).find("landmarks"), std::string::npos);
}

TEST_F(VerdictOnEllipsoid, AMapWithARegionSentToTheOtherEndTearsAndIsSuspect) {
  // The true map, except that the end beyond y = 1 (of 1.6) is sent to the other end (the image of
  // the point opposite): right inside the region and outside it, torn along its border.
  std::vector<int> region_moved = truth_;
  const CleanMesh& clean = source_->clean();
  double top = 0;  // the clean mesh's coordinates are normalised
  for (const Vec3& p : clean.mesh.vertices) top = std::max(top, p.y());
  for (int c = 0; c < clean.mesh.num_vertices(); ++c) {
    if (clean.mesh.vertices[c].y() <= top / 1.6) continue;
    int opposite = 0;
    for (int w = 0; w < clean.mesh.num_vertices(); ++w)
      if ((clean.mesh.vertices[w] + clean.mesh.vertices[c]).squaredNorm() <
          (clean.mesh.vertices[opposite] + clean.mesh.vertices[c]).squaredNorm())
        opposite = w;
    region_moved[c] = truth_[opposite];
  }

  const MapTearing right = measure_map_tearing(*source_, *target_, truth_);
  EXPECT_GT(right.pairs, 0);
  EXPECT_EQ(right.torn_pairs, 0);
  const MapTearing torn = measure_map_tearing(*source_, *target_, region_moved);
  EXPECT_EQ(torn.pairs, right.pairs);
  EXPECT_GT(torn.torn_share(), kTornShare) << torn.torn_pairs << " of " << torn.pairs;
  EXPECT_GT(torn.torn_samples, 1);
  // The whole mirror image keeps every neighbourhood: it tears nothing.
  EXPECT_EQ(measure_map_tearing(*source_, *target_, mirror_).torn_pairs, 0);

  MatchResult result = chosen_over(mirror_, 1.5);
  result.quality.torn_share = torn.torn_share();
  const MatchVerdict verdict = diagnose(*source_, *target_, result);
  EXPECT_TRUE(verdict.suspect);
  ASSERT_EQ(verdict.reasons.size(), 1u);
  EXPECT_NE(verdict.reasons[0].find("tears the surface"), std::string::npos) << verdict.reasons[0];
  result.quality.torn_share = right.torn_share();
  EXPECT_FALSE(diagnose(*source_, *target_, result).suspect);
}

}  // namespace
}  // namespace isocorr
