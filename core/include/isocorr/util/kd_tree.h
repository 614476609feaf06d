// Implicit k-d tree over a subset of 3-D points, for nearest-point and radius queries.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace isocorr {

// Every index range is split at its median, along x, y, z in turn with depth; the tree is
// the reordered id list, nothing else. Used by mesh cleaning for welding (radius queries)
// and for the nearest kept vertex of a dropped one.
class KdTree {
 public:
  // `points` must outlive the tree; `ids` are the indices into `points` the tree holds.
  KdTree(const std::vector<Eigen::Vector3d>& points, std::vector<int> ids);

  // The id of the held point closest to `query`; -1 when the tree is empty.
  int nearest(const Eigen::Vector3d& query) const;

  // Calls visit(id) for every held point within `radius` of `query` (distance <= radius).
  template <class Visit>
  void within(const Eigen::Vector3d& query, double radius, const Visit& visit) const {
    within(0, ids_.size(), 0, query, radius, visit);
  }

 private:
  void build(size_t lo, size_t hi, int axis);
  void nearest(size_t lo, size_t hi, int axis, const Eigen::Vector3d& query, int& best, double& best_squared) const;

  template <class Visit>
  void within(size_t lo, size_t hi, int axis, const Eigen::Vector3d& query, double radius, const Visit& visit) const {
    if (lo >= hi) return;
    const size_t mid = lo + (hi - lo) / 2;
    const Eigen::Vector3d& split = points_[ids_[mid]];
    if ((split - query).squaredNorm() <= radius * radius) visit(ids_[mid]);
    const double offset = query[axis] - split[axis];
    if (offset <= radius) within(lo, mid, (axis + 1) % 3, query, radius, visit);
    if (offset >= -radius) within(mid + 1, hi, (axis + 1) % 3, query, radius, visit);
  }

  const std::vector<Eigen::Vector3d>& points_;
  std::vector<int> ids_;
};

}  // namespace isocorr
