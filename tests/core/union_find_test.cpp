// UnionFind: merged elements share a root, and the root is the smallest member.
#include "isocorr/util/union_find.h"

#include <gtest/gtest.h>

namespace isocorr {
namespace {

TEST(UnionFind, StartsWithSingletons) {
  UnionFind sets(4);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(sets.find(i), i);
}

TEST(UnionFind, MergesTransitivelyWithTheSmallestMemberAsRoot) {
  UnionFind sets(8);
  sets.unite(5, 7);
  sets.unite(7, 3);
  sets.unite(1, 6);
  EXPECT_EQ(sets.find(5), 3);
  EXPECT_EQ(sets.find(7), 3);
  EXPECT_EQ(sets.find(3), 3);
  EXPECT_EQ(sets.find(6), 1);
  EXPECT_EQ(sets.find(0), 0);
  sets.unite(6, 5);  // joins the two groups
  for (int i : {1, 3, 5, 6, 7}) EXPECT_EQ(sets.find(i), 1);
  sets.unite(3, 7);  // already together: no change
  EXPECT_EQ(sets.find(7), 1);
  EXPECT_EQ(sets.find(2), 2);
  EXPECT_EQ(sets.find(4), 4);
}

TEST(UnionFind, LongChainsCollapse) {
  const int size = 100000;
  UnionFind sets(size);
  for (int i = size - 1; i > 0; --i) sets.unite(i, i - 1);
  for (int i = 0; i < size; ++i) ASSERT_EQ(sets.find(i), 0);
}

}  // namespace
}  // namespace isocorr
