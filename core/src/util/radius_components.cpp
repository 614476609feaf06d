#include "isocorr/util/radius_components.h"

#include <algorithm>
#include <numeric>

namespace isocorr {
namespace {

// An implicit k-d tree (every range split at its median, x, y, z in turn) from which points
// are taken out once reported. The node of a range [lo, hi) is its middle slot, which holds
// the range's split point and how many points of the range are still in the tree.
class ShrinkingKdTree {
 public:
  ShrinkingKdTree(const std::vector<Eigen::Vector3d>& points, std::vector<int> ids)
      : points_(points), ids_(std::move(ids)), remaining_(ids_.size()), slot_of_(points.size(), -1) {
    build(0, ids_.size(), 0);
    for (size_t slot = 0; slot < ids_.size(); ++slot) slot_of_[ids_[slot]] = static_cast<int>(slot);
  }

  bool contains(int id) const { return slot_of_[id] >= 0; }

  void remove(int id) {
    const size_t slot = slot_of_[id];
    size_t lo = 0, hi = ids_.size();
    for (;;) {
      const size_t mid = lo + (hi - lo) / 2;
      --remaining_[mid];
      if (slot == mid) break;
      if (slot < mid) hi = mid;
      else lo = mid + 1;
    }
    slot_of_[id] = -1;
  }

  // Calls take(id) for every point still in the tree within `radius` of `query`; `take` must
  // remove it.
  template <class Take>
  void take_within(const Eigen::Vector3d& query, double radius, const Take& take) {
    take_within(0, ids_.size(), 0, query, radius, take);
  }

 private:
  void build(size_t lo, size_t hi, int axis) {
    if (lo >= hi) return;
    const size_t mid = lo + (hi - lo) / 2;
    std::nth_element(ids_.begin() + lo, ids_.begin() + mid, ids_.begin() + hi,
                     [&](int a, int b) { return points_[a][axis] < points_[b][axis]; });
    remaining_[mid] = hi - lo;
    build(lo, mid, (axis + 1) % 3);
    build(mid + 1, hi, (axis + 1) % 3);
  }

  template <class Take>
  void take_within(size_t lo, size_t hi, int axis, const Eigen::Vector3d& query, double radius, const Take& take) {
    if (lo >= hi) return;
    const size_t mid = lo + (hi - lo) / 2;
    if (remaining_[mid] == 0) return;
    const int split_id = ids_[mid];
    const Eigen::Vector3d& split = points_[split_id];
    const double offset = query[axis] - split[axis];
    if (offset <= radius) take_within(lo, mid, (axis + 1) % 3, query, radius, take);
    if (offset >= -radius) take_within(mid + 1, hi, (axis + 1) % 3, query, radius, take);
    if (slot_of_[split_id] >= 0 && (split - query).squaredNorm() <= radius * radius) take(split_id);
  }

  const std::vector<Eigen::Vector3d>& points_;
  std::vector<int> ids_;
  std::vector<size_t> remaining_;
  std::vector<int> slot_of_;  // -1 once taken out
};

}  // namespace

std::vector<int> radius_components(const std::vector<Eigen::Vector3d>& points, std::vector<int> candidates,
                                   double radius) {
  std::vector<int> group(points.size());
  std::iota(group.begin(), group.end(), 0);
  std::sort(candidates.begin(), candidates.end());
  ShrinkingKdTree tree(points, candidates);
  std::vector<int> frontier;
  // In increasing order, the first candidate still in the tree is its group's smallest id;
  // its group is everything reachable from it through the points still in the tree.
  for (const int first : candidates) {
    if (!tree.contains(first)) continue;
    tree.remove(first);
    frontier.assign(1, first);
    while (!frontier.empty()) {
      const int at = frontier.back();
      frontier.pop_back();
      tree.take_within(points[at], radius, [&](int id) {
        tree.remove(id);
        group[id] = first;
        frontier.push_back(id);
      });
    }
  }
  return group;
}

}  // namespace isocorr
