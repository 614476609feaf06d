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
  // Coordinates by axis, so that the distance update runs in vector registers; then the
  // farthest vertex as the first one holding the largest distance. The scalar loop that
  // did both at once waited on its running maximum (0.45 s for 2000 samples of a 52K mesh).
  std::vector<double> x(n), y(n), z(n);
  for (int v = 0; v < n; ++v) x[v] = mesh.vertices[v].x(), y[v] = mesh.vertices[v].y(), z[v] = mesh.vertices[v].z();
  std::vector<float> distance(n, std::numeric_limits<float>::max());
  std::vector<int> chosen;
  chosen.reserve(count);
  int next = 0;
  while (static_cast<int>(chosen.size()) < count) {
    chosen.push_back(next);
    const double px = x[next], py = y[next], pz = z[next];
    for (int v = 0; v < n; ++v) {
      const double dx = x[v] - px, dy = y[v] - py, dz = z[v] - pz;
      distance[v] = std::min(distance[v], static_cast<float>(dx * dx + dy * dy + dz * dz));
    }
    next = static_cast<int>(std::max_element(distance.begin(), distance.end()) - distance.begin());
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
