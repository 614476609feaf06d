#include "isocorr/util/kd_tree.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace isocorr {

KdTree::KdTree(const std::vector<Eigen::Vector3d>& points, std::vector<int> ids)
    : points_(points), ids_(std::move(ids)) {
  build(0, ids_.size(), 0);
}

int KdTree::nearest(const Eigen::Vector3d& query) const {
  int best = -1;
  double best_squared = std::numeric_limits<double>::infinity();
  nearest(0, ids_.size(), 0, query, best, best_squared);
  return best;
}

void KdTree::build(size_t lo, size_t hi, int axis) {
  if (hi - lo < 2) return;
  const size_t mid = lo + (hi - lo) / 2;
  std::nth_element(ids_.begin() + lo, ids_.begin() + mid, ids_.begin() + hi,
                   [&](int a, int b) { return points_[a][axis] < points_[b][axis]; });
  build(lo, mid, (axis + 1) % 3);
  build(mid + 1, hi, (axis + 1) % 3);
}

void KdTree::nearest(size_t lo, size_t hi, int axis, const Eigen::Vector3d& query, int& best,
                     double& best_squared) const {
  if (lo >= hi) return;
  const size_t mid = lo + (hi - lo) / 2;
  const Eigen::Vector3d& split = points_[ids_[mid]];
  const double squared = (split - query).squaredNorm();
  if (squared < best_squared) best_squared = squared, best = ids_[mid];
  const double offset = query[axis] - split[axis];
  const int next = (axis + 1) % 3;
  // Near side first; the far side only if the splitting plane is closer than the best.
  if (offset < 0) nearest(lo, mid, next, query, best, best_squared);
  else nearest(mid + 1, hi, next, query, best, best_squared);
  if (offset * offset < best_squared) {
    if (offset < 0) nearest(mid + 1, hi, next, query, best, best_squared);
    else nearest(lo, mid, next, query, best, best_squared);
  }
}

}  // namespace isocorr
