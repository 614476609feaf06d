#include "isocorr/geodesic/geodesic_diameter.h"

#include <algorithm>

namespace isocorr {

double estimate_geodesic_diameter(const FastMarching& geodesics, int sweeps) {
  FastMarching::Workspace ws;
  int from = 0;
  double diameter = 0;
  for (int sweep = 0; sweep < std::max(1, sweeps); ++sweep) {
    geodesics.compute({from}, ws);
    int farthest = from;
    for (int v = 0; v < static_cast<int>(ws.distance.size()); ++v)
      if (ws.distance[v] != kUnreached && ws.distance[v] > ws.distance[farthest]) farthest = v;
    if (ws.distance[farthest] <= diameter) break;
    diameter = ws.distance[farthest];
    from = farthest;
  }
  return diameter > 0 ? diameter : 1.0;
}

}  // namespace isocorr
