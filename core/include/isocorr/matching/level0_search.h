// Level 0 of C2FCM: every injective map of M source samples into M' target samples,
// scored by isometric distortion D_iso and sorted (paper Eq. 1).
#pragma once

#include <vector>

#include <Eigen/Core>

namespace isocorr {

struct Level0Map {
  std::vector<int> target_of;  // target sample index for each of the M source samples
  double diso = 0;             // D_iso of the map on its own samples
};

// `source_distances` M x M and `target_distances` M' x M' hold normalised geodesic
// distances between the samples. Returns the maps with D_iso < max_diso, ascending (ties
// broken lexicographically, so the list is deterministic), at most `max_maps` of them.
// Branches are pruned with an exact lower bound (the distortion of the pairs fixed so far
// can only grow), so nothing under the threshold is missed.
std::vector<Level0Map> search_level0(const Eigen::MatrixXd& source_distances,
                                     const Eigen::MatrixXd& target_distances, double max_diso,
                                     int max_maps, int threads);

// What drop_level0_maps did.
struct Level0Drop {
  int dropped = 0;           // maps removed
  bool none_agreed = false;  // every map disagreed: the least disagreeing one was kept
};

// Removes the maps whose `disagreement` (one per map, in the order of `maps`; the
// landmarks' measure, transfer/landmarks.h) exceeds `max_disagreement`, keeping the order
// of the rest. Never leaves none: when every map disagrees, the least disagreeing one
// stays (the first of equals) and the outcome says so.
Level0Drop drop_level0_maps(std::vector<Level0Map>& maps, const std::vector<double>& disagreement,
                            double max_disagreement);

// The paper's jump rule (Sec. 4): delta = 2 * mean(D_l - D_{l-1}, l = 2..11); N is the
// first index with D_{N+1} - D_N > delta. Returns N (>= 1 when the list is non-empty).
int jump_rule_count(const std::vector<Level0Map>& sorted_maps);

}  // namespace isocorr
