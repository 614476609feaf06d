#include "isocorr/sampling/vertex_spreading.h"

#include <algorithm>
#include <limits>
#include <queue>

namespace isocorr {

std::vector<int> spread_vertices(const TriangleMesh& mesh, int count) {
  const int n = mesh.num_vertices();
  if (count >= n) {
    std::vector<int> all(n);
    for (int v = 0; v < n; ++v) all[v] = v;
    return all;
  }
  std::vector<float> distance(n, std::numeric_limits<float>::max());
  std::vector<int> chosen;
  chosen.reserve(count);
  int next = 0;
  while (static_cast<int>(chosen.size()) < count) {
    chosen.push_back(next);
    const Vec3 p = mesh.vertices[next];
    int farthest = 0;
    for (int v = 0; v < n; ++v) {
      distance[v] = std::min(distance[v], static_cast<float>((mesh.vertices[v] - p).squaredNorm()));
      if (distance[v] > distance[farthest]) farthest = v;
    }
    next = farthest;
  }
  return chosen;
}

std::vector<int> nearest_centre(const MeshTopology& topology, int vertex_count, const std::vector<int>& centres) {
  std::vector<int> owner(vertex_count, -1);
  std::queue<int> frontier;
  for (size_t c = 0; c < centres.size(); ++c)
    if (owner[centres[c]] < 0) owner[centres[c]] = static_cast<int>(c), frontier.push(centres[c]);
  while (!frontier.empty()) {
    const int v = frontier.front();
    frontier.pop();
    for (const int* u = topology.neighbours_begin(v); u != topology.neighbours_end(v); ++u)
      if (owner[*u] < 0) owner[*u] = owner[v], frontier.push(*u);
  }
  for (int& o : owner) o = std::max(o, 0);
  return owner;
}

}  // namespace isocorr
