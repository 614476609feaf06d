// radius_components: groups by transitive closeness, the smallest id leading, and linear
// behaviour where many points coincide (a pairwise search never finishes on the last test).
#include "isocorr/util/radius_components.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace isocorr {
namespace {

using Points = std::vector<Eigen::Vector3d>;

TEST(RadiusComponents, JoinsChainsAndLeavesFarPointsAndNonCandidatesAlone) {
  // 0-1-2 a chain (each step 0.9, ends 1.8 apart), 3 far, 4 on top of 0 but no candidate.
  const Points points = {{0, 0, 0}, {0.9, 0, 0}, {1.8, 0, 0}, {10, 0, 0}, {0, 0, 0}};
  const std::vector<int> group = radius_components(points, {2, 1, 0, 3}, 1.0);
  EXPECT_EQ(group, (std::vector<int>{0, 0, 0, 3, 4}));
}

TEST(RadiusComponents, DistanceEqualToTheRadiusJoins) {
  const Points points = {{0, 0, 0}, {0, 0, 0.5}, {0, 0, 1.5}};
  EXPECT_EQ(radius_components(points, {0, 1, 2}, 0.5), (std::vector<int>{0, 0, 2}));
}

TEST(RadiusComponents, AgreesWithPairwiseClosureOnRandomPoints) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(0, 1);
  Points points(400);
  for (auto& p : points) p = {uniform(random), uniform(random), uniform(random)};
  std::vector<int> candidates;
  for (int i = 0; i < 400; i += 2) candidates.push_back(i);
  const double radius = 0.08;
  const std::vector<int> group = radius_components(points, candidates, radius);
  // Pairwise closure by repeated relaxation to the smallest id.
  std::vector<int> expected(points.size());
  for (size_t i = 0; i < points.size(); ++i) expected[i] = static_cast<int>(i);
  for (bool changed = true; changed;) {
    changed = false;
    for (int a : candidates)
      for (int b : candidates)
        if ((points[a] - points[b]).norm() <= radius && expected[b] > expected[a]) expected[b] = expected[a], changed = true;
  }
  EXPECT_EQ(group, expected);
}

TEST(RadiusComponents, MillionsOfCoincidentPointsFormOneGroup) {
  Points points(2'000'000, Eigen::Vector3d(0.5, 0.5, 0.5));
  points.push_back({3, 3, 3});
  std::vector<int> candidates(points.size());
  for (size_t i = 0; i < candidates.size(); ++i) candidates[i] = static_cast<int>(i);
  const std::vector<int> group = radius_components(points, candidates, 1e-9);
  for (size_t i = 0; i + 1 < points.size(); ++i) ASSERT_EQ(group[i], 0) << i;
  EXPECT_EQ(group.back(), static_cast<int>(points.size()) - 1);
}

}  // namespace
}  // namespace isocorr
