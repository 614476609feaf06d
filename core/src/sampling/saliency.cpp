#include "isocorr/sampling/saliency.h"

#include <algorithm>
#include <numeric>

#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

int argmax(const std::vector<float>& values) {
  int best = 0;
  for (int v = 1; v < static_cast<int>(values.size()); ++v)
    if (values[v] > values[best] && values[v] != kUnreached) best = v;
  return best;
}

}  // namespace

Saliency compute_saliency(const FastMarching& geodesics, const SaliencyOptions& options,
                          int threads, const JobControl& control) {
  const TriangleMesh& mesh = geodesics.mesh();
  const int n = mesh.num_vertices();
  Saliency result;
  std::vector<double> agd_sum(n, 0.0);
  std::vector<float> nearest_source(n, kUnreached);

  // Farthest-point sweep: the first source is the vertex farthest from vertex 0, so the
  // first field already spans the diameter.
  FastMarching::Workspace ws;
  geodesics.compute({0}, ws);
  int source = argmax(ws.distance);
  const int sources = std::max(1, std::min(options.agd_sources, n));
  double diameter = 0;
  for (int i = 0; i < sources; ++i) {
    control.check_cancelled();
    geodesics.compute({source}, ws);
    for (int v = 0; v < n; ++v) {
      const float d = ws.distance[v];
      if (d == kUnreached) continue;
      agd_sum[v] += d;
      nearest_source[v] = std::min(nearest_source[v], d);
      diameter = std::max(diameter, static_cast<double>(d));
    }
    source = argmax(nearest_source);
  }
  result.diameter = diameter > 0 ? diameter : 1.0;
  result.agd.resize(n);
  for (int v = 0; v < n; ++v)
    result.agd[v] = static_cast<float>(agd_sum[v] / sources / result.diameter);

  // Extremities: one-ring maxima of AGD that are also maxima within the extremity radius.
  const MeshTopology& topology = geodesics.topology();
  std::vector<int> ring_maxima;
  for (int v = 0; v < n; ++v) {
    bool is_max = topology.neighbours_begin(v) != topology.neighbours_end(v);
    for (const int* w = topology.neighbours_begin(v); w != topology.neighbours_end(v) && is_max; ++w)
      if (result.agd[*w] > result.agd[v] || (result.agd[*w] == result.agd[v] && *w < v)) is_max = false;
    if (is_max) ring_maxima.push_back(v);
  }
  std::vector<unsigned char> keep(ring_maxima.size(), 0);
  const float radius = static_cast<float>(options.extremity_radius * result.diameter);
  const int workers = resolve_thread_count(threads);
  std::vector<FastMarching::Workspace> workspaces(workers);
  parallel_for(static_cast<int>(ring_maxima.size()), workers, [&](int i, int worker) {
    control.check_cancelled();
    const int v = ring_maxima[i];
    auto& w = workspaces[worker];
    geodesics.compute({v}, w, radius);
    keep[i] = 1;
    for (int u : w.touched)
      if (w.distance[u] != kUnreached && result.agd[u] > result.agd[v]) {
        keep[i] = 0;
        break;
      }
  });
  for (size_t i = 0; i < ring_maxima.size(); ++i)
    if (keep[i]) result.extremities.push_back(ring_maxima[i]);
  auto by_agd = [&](int a, int b) {
    return result.agd[a] != result.agd[b] ? result.agd[a] > result.agd[b] : a < b;
  };
  std::sort(result.extremities.begin(), result.extremities.end(), by_agd);


  std::vector<unsigned char> is_extremity(n, 0);
  for (int v : result.extremities) is_extremity[v] = 1;
  result.order = result.extremities;
  std::vector<int> rest;
  rest.reserve(n);
  for (int v = 0; v < n; ++v)
    if (!is_extremity[v]) rest.push_back(v);
  std::sort(rest.begin(), rest.end(), by_agd);
  result.order.insert(result.order.end(), rest.begin(), rest.end());
  return result;
}

}  // namespace isocorr
