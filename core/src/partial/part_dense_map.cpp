#include "part_dense_map.h"

#include <algorithm>
#include <functional>
#include <queue>

#include "isocorr/geodesic/fast_marching.h"
#include "isocorr/matching/surface_descent.h"
#include "isocorr/partial/part_matching.h"
#include "isocorr/util/parallel.h"
#include "part_growth.h"

namespace isocorr {
namespace {

// Dense anchors weigh 1 / (distance + kLocality): near pairs count more (as the C2F dense level).
constexpr double kLocality = 0.05;
// A target vertex is covered by the part's image when an image lies within this many
// mean edge lengths of it.
constexpr double kCoverEdges = 2.5;
// A rough candidate's orientation is measured on the faces around every this-many-th
// spectral sample (farthest-point order: spread over the part).
constexpr int kOrientationSampleStride = 4;

}  // namespace

VisitOrder breadth_first_order(const PreprocessedShape& shape, int start) {
  const MeshTopology& topology = shape.geodesics().topology();
  VisitOrder visit;
  visit.parent.assign(shape.mesh().num_vertices(), -1);
  std::vector<char> seen(shape.mesh().num_vertices(), 0);
  visit.order.reserve(seen.size());
  std::queue<int> queue;
  queue.push(start);
  seen[start] = 1;
  while (!queue.empty()) {
    const int v = queue.front();
    queue.pop();
    visit.order.push_back(v);
    for (const int* u = topology.neighbours_begin(v); u != topology.neighbours_end(v); ++u)
      if (!seen[*u]) seen[*u] = 1, visit.parent[*u] = v, queue.push(*u);
  }
  return visit;
}

std::vector<char> rough_map_vertices(const PreprocessedShape& source) {
  const MeshTopology& topology = source.geodesics().topology();
  std::vector<char> wanted(source.mesh().num_vertices(), 0);
  const std::vector<int>& samples = source.spectral_samples();
  for (size_t i = 0; i < samples.size(); ++i) {
    wanted[samples[i]] = 1;
    if (i % kOrientationSampleStride == 0)
      for (const int* u = topology.neighbours_begin(samples[i]); u != topology.neighbours_end(samples[i]); ++u)
        wanted[*u] = 1;
  }
  return wanted;
}

void fill_from_parents(const VisitOrder& visit, int fallback, std::vector<int>& forward) {
  for (const int v : visit.order)
    if (forward[v] < 0 && visit.parent[v] >= 0) forward[v] = forward[visit.parent[v]];
  for (int& t : forward)
    if (t < 0) t = fallback;  // unreachable from the first vertex, as in dense_part_map
}

TargetAnchors sample_anchors(const PreprocessedShape& target, const std::vector<SamplePair>& pairs) {
  TargetAnchors anchors;
  for (const SamplePair& p : pairs) {
    anchors.vertex.push_back(target.sample_vertex(p.target_sample));
    anchors.rows.push_back(target.field_row(p.target_sample));
  }
  anchors.row_scale = static_cast<float>(target.diameter());
  return anchors;
}

TargetAnchors vertex_accurate_anchors(const PartGeometry& part, const std::vector<SamplePair>& pairs, double scale,
                                      int threads, const JobControl& control) {
  const PreprocessedShape& target = part.target;
  TargetAnchors anchors;
  const int count = static_cast<int>(pairs.size());
  anchors.vertex.resize(count);
  anchors.computed_fields.resize(count);
  const float target_diameter = static_cast<float>(target.diameter());
  const float scale_f = static_cast<float>(scale);
  parallel_for(count, threads, [&](int q, int) {
    control.check_cancelled();
    const int sv = part.shape.sample_vertex(pairs[q].source_sample);
    std::vector<float> gs(count);
    std::vector<char> exact(count);
    for (int p = 0; p < count; ++p) {
      gs[p] = part.distance(pairs[p].source_sample, sv);
      exact[p] = part.exact(pairs[p].source_sample, sv, gs[p]);
    }
    std::vector<float> terms;
    auto cost = [&](int t) {
      terms.clear();
      for (int p = 0; p < count; ++p) {
        if (p == q) continue;
        const float gt = target.field(pairs[p].target_sample, t) * target_diameter;
        terms.push_back(mismatch(gs[p], gt * scale_f, exact[p],
                                 part.target_exact(target.sample_vertex(pairs[p].target_sample), t, gt)));
      }
      return trimmed_mean(terms);
    };
    float best = 0;
    anchors.vertex[q] = descend_to_minimum<CostPrice::kDear>(
        target.geodesics().topology(), target.sample_vertex(pairs[q].target_sample), cost, best);
    anchors.computed_fields[q] = target.geodesics().distance_field(anchors.vertex[q]);
  });
  for (const auto& field : anchors.computed_fields) anchors.rows.push_back(field.data());
  anchors.row_scale = 1;
  return anchors;
}

DenseMap dense_part_map(const PartGeometry& part, const TrackedMap& chosen, const TargetAnchors& anchors, double scale,
                        const VisitOrder& visit, const std::vector<char>& wanted, const JobControl& control) {
  const PreprocessedShape& source = part.shape;
  const PreprocessedShape& target = part.target;
  const int source_vertices = source.mesh().num_vertices();
  const float scale_f = static_cast<float>(scale);
  const float source_diameter = static_cast<float>(source.diameter());
  const auto& pairs = chosen.pairs;
  DenseMap dense;
  dense.forward.assign(source_vertices, -1);
  dense.forward_diso.assign(source_vertices, 0.0f);

  // Per pair, what does not depend on the vertex: this loop runs once per source vertex
  // and candidate, its cost function some 25 times per vertex (64 candidates of a 28K
  // part: most of a part match's time).
  const size_t count = pairs.size();
  std::vector<const float*> source_rows(count);
  std::vector<float> sample_boundary(count), anchor_boundary(count);
  for (size_t a = 0; a < count; ++a) {
    source_rows[a] = source.field_row(pairs[a].source_sample);
    sample_boundary[a] = part.boundary_distance[source.sample_vertex(pairs[a].source_sample)];
    anchor_boundary[a] = part.target_boundary_distance[anchors.vertex[a]];
  }
  std::vector<float> gs(count), weight(count);
  std::vector<char> exact(count);
  const MeshTopology& source_topology = source.geodesics().topology();
  const MeshTopology& target_topology = target.geodesics().topology();
  const std::vector<int>& order = visit.order;
  for (size_t k = 0; k < order.size(); ++k) {
    if (k % 4096 == 0) control.check_cancelled();
    const int v = order[k];
    if (!wanted.empty() && !wanted[v]) continue;
    const float vertex_boundary = part.boundary_distance[v];
    double total = 0;
    for (size_t a = 0; a < count; ++a) {
      gs[a] = source_rows[a][v] * source_diameter;  // part.distance
      exact[a] = gs[a] < sample_boundary[a] + vertex_boundary;  // part.exact
      weight[a] = 1.0f / (gs[a] / source_diameter + static_cast<float>(kLocality));
      total += weight[a];
    }
    auto cost = [&](int t) {
      const float target_boundary = part.target_boundary_distance[t];
      double sum = 0;
      for (size_t a = 0; a < count; ++a) {
        const float gt = anchors.rows[a][t] * anchors.row_scale;
        sum += weight[a] * mismatch(gs[a], gt * scale_f, exact[a], gt < anchor_boundary[a] + target_boundary);
      }
      return static_cast<float>(sum / total);
    };
    // Start at a visited neighbour's image, else at the nearest visited ancestor's, else at
    // the nearest anchor's image.
    int start = -1;
    for (const int* u = source_topology.neighbours_begin(v); u != source_topology.neighbours_end(v) && start < 0; ++u)
      start = dense.forward[*u];
    for (int u = visit.parent[v]; u >= 0 && start < 0; u = visit.parent[u]) start = dense.forward[u];
    if (start < 0) {
      size_t nearest = 0;
      for (size_t a = 1; a < pairs.size(); ++a)
        if (gs[a] < gs[nearest]) nearest = a;
      start = anchors.vertex[nearest];
    }
    float best = 0;
    dense.forward[v] = descend_to_minimum<CostPrice::kDear>(target_topology, start, cost, best);
    dense.forward_diso[v] = best / source_diameter;
  }
  for (int v = 0; v < source_vertices; ++v)  // unreachable from the first vertex: cannot happen on a cleaned mesh
    if (dense.forward[v] < 0 && (wanted.empty() || wanted[v]))
      dense.forward[v] = target.sample_vertex(pairs.front().target_sample);
  return dense;
}

double covered_share(const PreprocessedShape& source, const PreprocessedShape& target,
                     const std::vector<double>& target_vertex_areas, double scale, DenseMap& map) {
  add_part_reverse_map(source, target, scale, map);
  const double expected_share = source.area() / (scale * scale * target.area());
  return expected_share > 0 ? matched_area_share(target_vertex_areas, map.reverse) / expected_share : 0;
}

// Edge-graph Dijkstra from the images, carrying their source vertices.
void add_part_reverse_map(const PreprocessedShape& source, const PreprocessedShape& target, double scale,
                          DenseMap& dense) {
  const int source_vertices = source.mesh().num_vertices();
  const MeshTopology& target_topology = target.geodesics().topology();
  const TriangleMesh& tm = target.mesh();
  const int target_vertices = tm.num_vertices();
  dense.reverse.assign(target_vertices, -1);
  dense.reverse_diso.assign(target_vertices, kUnreached);
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> heap;
  for (int v = 0; v < source_vertices; ++v) {
    const int t = dense.forward[v];
    if (dense.reverse[t] < 0 || dense.forward_diso[v] < dense.forward_diso[dense.reverse[t]]) dense.reverse[t] = v;
    dense.reverse_diso[t] = 0;
  }
  for (int t = 0; t < target_vertices; ++t)
    if (dense.reverse[t] >= 0) heap.push({0.0f, t});
  const float reach = static_cast<float>(kCoverEdges * std::max(target.mean_edge(), source.mean_edge() / scale));
  while (!heap.empty()) {
    const auto [d, t] = heap.top();
    heap.pop();
    if (d > dense.reverse_diso[t]) continue;
    for (const int* u = target_topology.neighbours_begin(t); u != target_topology.neighbours_end(t); ++u) {
      const float nd = d + static_cast<float>((tm.vertices[*u] - tm.vertices[t]).norm());
      if (nd <= reach && nd < dense.reverse_diso[*u]) {
        dense.reverse_diso[*u] = nd;
        dense.reverse[*u] = dense.reverse[t];
        heap.push({nd, *u});
      }
    }
  }
  for (float& d : dense.reverse_diso)
    if (d != kUnreached) d /= static_cast<float>(target.diameter());
}

double matched_area_share(const std::vector<double>& areas, const std::vector<int>& reverse) {
  double matched = 0, total = 0;
  for (size_t t = 0; t < areas.size(); ++t) total += areas[t], matched += reverse[t] >= 0 ? areas[t] : 0;
  return total > 0 ? matched / total : 0;
}

}  // namespace isocorr
