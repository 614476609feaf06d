#include "isocorr/sampling/salient_sampling.h"

#include <algorithm>

namespace isocorr {

SampleSet evenly_spaced_salient_sampling(const FastMarching& geodesics,
                                         const std::vector<int>& order,
                                         const SamplingSchedule& schedule) {
  const int n = geodesics.mesh().num_vertices();
  SampleSet samples;
  // Distance from each vertex to its nearest accepted sample. Fields are cut off at the
  // current radius: radii only shrink, so farther values are never needed again.
  std::vector<float> nearest(n, kUnreached);
  std::vector<unsigned char> accepted(n, 0);
  FastMarching::Workspace ws;
  for (size_t step = 0; step < schedule.radii.size(); ++step) {
    const float radius = static_cast<float>(schedule.radii[step]);
    const int cap = step < schedule.max_new.size() ? schedule.max_new[step] : 0;
    int added = 0;
    for (int v : order) {
      if (cap > 0 && added >= cap) break;
      if (accepted[v] || nearest[v] < radius) continue;
      accepted[v] = 1;
      samples.vertices.push_back(v);
      samples.step.push_back(static_cast<int>(step));
      ++added;
      geodesics.compute({v}, ws, radius);
      for (int u : ws.touched)
        nearest[u] = std::min(nearest[u], ws.distance[u]);
    }
  }
  return samples;
}

}  // namespace isocorr
