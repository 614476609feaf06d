// Groups of points joined, directly or through others, by distances within a radius.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace isocorr {

// For every index in [0, points.size()), the smallest id of its group: ids in `candidates`
// within `radius` of each other (distance <= radius) share a group, transitively; every other
// index is its own group. O(n log n) for any layout, however many points coincide: a k-d tree
// whose subtrees count the points not grouped yet, so each point is reported once.
std::vector<int> radius_components(const std::vector<Eigen::Vector3d>& points, std::vector<int> candidates,
                                   double radius);

}  // namespace isocorr
