#include "isocorr/util/assignment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

namespace isocorr {
namespace {

double total(const std::vector<std::vector<double>>& weight, const std::vector<int>& assignment) {
  double sum = 0;
  for (size_t r = 0; r < assignment.size(); ++r)
    if (assignment[r] >= 0) sum += weight[r][assignment[r]];
  return sum;
}

// The best total over every injective assignment of rows to columns (rows <= columns).
double brute_force_best(const std::vector<std::vector<double>>& weight) {
  const int rows = static_cast<int>(weight.size()), cols = static_cast<int>(weight[0].size());
  std::vector<int> columns(cols);
  std::iota(columns.begin(), columns.end(), 0);
  double best = -1e300;
  do {
    double sum = 0;
    for (int r = 0; r < rows; ++r) sum += weight[r][columns[r]];
    best = std::max(best, sum);
  } while (std::next_permutation(columns.begin(), columns.end()));
  return best;
}

TEST(MaxWeightAssignment, PrefersTheBestTotalOverGreedyChoices) {
  // Greedy takes (0,0) = 10 and is left with 1; the optimum pairs 0-1 and 1-0 for 9 + 9.
  const std::vector<std::vector<double>> weight = {{10, 9}, {9, 1}};
  EXPECT_EQ(max_weight_assignment(weight), (std::vector<int>{1, 0}));
}

TEST(MaxWeightAssignment, MatchesBruteForceOnRectangularMatrices) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(0, 1);
  for (int trial = 0; trial < 40; ++trial) {
    const int rows = 2 + trial % 4, cols = rows + trial % 3;
    std::vector<std::vector<double>> weight(rows, std::vector<double>(cols));
    for (auto& row : weight)
      for (double& w : row) w = uniform(random) < 0.3 ? 0 : uniform(random);
    const std::vector<int> assignment = max_weight_assignment(weight);
    ASSERT_EQ(assignment.size(), static_cast<size_t>(rows));
    std::vector<int> used;
    for (int c : assignment) {
      ASSERT_GE(c, 0);
      ASSERT_LT(c, cols);
      used.push_back(c);
    }
    std::sort(used.begin(), used.end());
    EXPECT_EQ(std::unique(used.begin(), used.end()), used.end()) << "a column used twice";
    EXPECT_NEAR(total(weight, assignment), brute_force_best(weight), 1e-12) << "trial " << trial;
  }
}

TEST(MaxWeightAssignment, LeavesSurplusRowsUnassigned) {
  const std::vector<std::vector<double>> weight = {{1}, {5}, {2}};
  EXPECT_EQ(max_weight_assignment(weight), (std::vector<int>{-1, 0, -1}));
}

}  // namespace
}  // namespace isocorr
