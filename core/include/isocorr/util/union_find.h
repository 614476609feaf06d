// Disjoint sets over 0..size-1 with path halving.
#pragma once

#include <algorithm>
#include <numeric>
#include <vector>

namespace isocorr {

// Union-find whose root is always the smallest member, so that a group is represented by
// its first element (mesh cleaning: a welded group by its first input vertex).
class UnionFind {
 public:
  explicit UnionFind(int size) : parent_(size) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

}  // namespace isocorr
