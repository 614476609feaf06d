// The final rigidity polish: kept only where the curvature agrees better.
#include <gtest/gtest.h>

#include "isocorr/refinement/final_polish.h"
#include "isocorr/refinement/rigidity_polish.h"
#include "refinement_fixtures.h"

namespace isocorr {
namespace {

using test_support::TwistedCopy;

// The final polish on a 20-degree twist polished briefly (so that some twist is left): the
// longer polish pulls it back further, the curvature agrees better along it, and it is
// kept. On the true map there is nothing to gain: the map is left as it was.
TEST(FinalPolish, KeptWhereTheCurvatureAgreesBetterOnly) {
  TwistedCopy twist(20);
  RigidityOptions options;
  options.iterations = 2;
  rigidity_polish(*twist.source, *twist.target, options, twist.map);
  const double before = twist.mean_error(twist.map.image);
  ASSERT_GT(before, 0);

  const FinalPolishOutcome twisted = extend_rigidity_polish(*twist.source, *twist.target, 40, 2, twist.map);
  EXPECT_TRUE(twisted.kept);
  EXPECT_LT(twisted.curvature_after, twisted.curvature_before);
  EXPECT_LT(twist.mean_error(twist.map.image), 0.5 * before);

  SpectralMap exact;
  exact.image = twist.copy.permutation;
  exact.reverse_image = twist.inverse;
  const FinalPolishOutcome untouched = extend_rigidity_polish(*twist.source, *twist.target, 40, 2, exact);
  EXPECT_FALSE(untouched.kept);
  EXPECT_GE(untouched.curvature_after, untouched.curvature_before);
  EXPECT_EQ(exact.image, twist.copy.permutation);
  EXPECT_EQ(exact.reverse_image, twist.inverse);
}

}  // namespace
}  // namespace isocorr
