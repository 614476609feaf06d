// Level-0 enumeration and the jump rule on hand-made inputs.
#include "isocorr/matching/level0_search.h"

#include <gtest/gtest.h>

namespace isocorr {
namespace {

Eigen::MatrixXd distances_of(const std::vector<double>& x) {
  const int n = static_cast<int>(x.size());
  Eigen::MatrixXd d(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) d(i, j) = std::abs(x[i] - x[j]);
  return d;
}

TEST(Level0Search, FindsTheExactPermutationFirst) {
  // Points on a line at irregular positions: only the identity (and no mirror, thanks to
  // the irregular spacing) has zero distortion. The target lists them in another order.
  const std::vector<double> source = {0.0, 0.13, 0.41, 0.52, 0.9};
  const std::vector<int> order = {3, 0, 4, 1, 2};  // target index of source i
  std::vector<double> target(5);
  for (int i = 0; i < 5; ++i) target[order[i]] = source[i];
  const auto maps = search_level0(distances_of(source), distances_of(target), 0.5, 1000, 2);
  ASSERT_FALSE(maps.empty());
  EXPECT_EQ(maps[0].target_of, order);
  EXPECT_NEAR(maps[0].diso, 0.0, 1e-12);
  for (size_t i = 1; i < maps.size(); ++i) EXPECT_LE(maps[i - 1].diso, maps[i].diso);
}

TEST(Level0Search, PruningKeepsEverythingUnderTheThreshold) {
  const std::vector<double> source = {0.0, 0.2, 0.45, 0.7};
  const std::vector<double> target = {0.05, 0.3, 0.5, 0.66, 0.95};
  const auto all = search_level0(distances_of(source), distances_of(target), 10.0, 100000, 1);
  EXPECT_EQ(all.size(), 5u * 4 * 3 * 2);  // every injective map
  const auto pruned = search_level0(distances_of(source), distances_of(target), 0.1, 100000, 2);
  size_t under = 0;
  for (const auto& m : all) under += m.diso < 0.1;
  EXPECT_EQ(pruned.size(), under);
}

Level0Map with_diso(double d) { return Level0Map{{}, d}; }

TEST(JumpRule, StopsAtTheFirstSignificantJump) {
  // Four near-equal maps (the symmetric variants), then a jump.
  std::vector<Level0Map> maps;
  for (double d : {0.020, 0.021, 0.022, 0.023, 0.060, 0.061, 0.062, 0.063, 0.064, 0.065, 0.066, 0.067})
    maps.push_back(with_diso(d));
  EXPECT_EQ(jump_rule_count(maps), 4);
}

TEST(JumpRule, EvenlySpacedListHasNoJump) {
  std::vector<Level0Map> maps;
  for (int i = 0; i < 12; ++i) maps.push_back(with_diso(0.01 * i));
  EXPECT_EQ(jump_rule_count(maps), 12);
  EXPECT_EQ(jump_rule_count({with_diso(0.1)}), 1);
  EXPECT_EQ(jump_rule_count({}), 0);
}

}  // namespace
}  // namespace isocorr
