#include "isocorr/matching/dense_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "isocorr/matching/surface_descent.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

// Vertex-major table of normalised distances to the anchors: row v holds E floats.
struct Descriptors {
  int anchors = 0;
  std::vector<float> values;
  const float* row(int v) const { return values.data() + static_cast<size_t>(v) * anchors; }
};

// Rows are fields over `shape` (one per anchor, normalised by its diameter).
Descriptors build_descriptors(int vertices, const std::vector<const float*>& fields) {
  Descriptors d;
  d.anchors = static_cast<int>(fields.size());
  d.values.resize(static_cast<size_t>(vertices) * d.anchors);
  for (int a = 0; a < d.anchors; ++a)
    for (int v = 0; v < vertices; ++v) d.values[static_cast<size_t>(v) * d.anchors + a] = fields[a][v];
  return d;
}

float l1(const float* x, const float* y, int count) {
  float sum = 0;
  for (int i = 0; i < count; ++i) sum += std::abs(x[i] - y[i]);
  return sum;
}

// Weighted L1: geodesic distortion of a near-isometry grows with distance, so near anchors
// are trusted more (weight 1 / (distance + locality)); weights sum to the anchor count so
// the result stays comparable with the plain form.
void locality_weights(const float* x, int count, float locality, float* weights) {
  float total = 0;
  for (int i = 0; i < count; ++i) total += weights[i] = 1.f / (x[i] + locality);
  const float scale = count / total;
  for (int i = 0; i < count; ++i) weights[i] *= scale;
}

float weighted_l1(const float* x, const float* y, const float* weights, int count) {
  float sum = 0;
  for (int i = 0; i < count; ++i) sum += weights[i] * std::abs(x[i] - y[i]);
  return sum;
}

// One direction: images on `to` for every vertex of `from`.
void match_direction(const PreprocessedShape& from, const Descriptors& from_desc,
                     const PreprocessedShape& to, const Descriptors& to_desc,
                     const std::vector<std::pair<int, int>>& seeds, float locality, int threads,
                     const JobControl& control, std::vector<int>& image,
                     std::vector<float>& cost) {
  const int n = from.mesh().num_vertices();
  const int e = from_desc.anchors;
  const MeshTopology& from_topology = from.geodesics().topology();
  const MeshTopology& to_topology = to.geodesics().topology();
  image.assign(n, -1);
  cost.assign(n, std::numeric_limits<float>::max());
  std::vector<int> start(n, -1);

  // Breadth-first layers from the seed vertices; each layer starts from the images found
  // in the previous one, and its vertices are independent of each other.
  std::vector<int> layer;
  for (const auto& [v, w] : seeds)
    if (start[v] < 0) start[v] = w, layer.push_back(v);
  std::sort(layer.begin(), layer.end());

  while (!layer.empty()) {
    control.check_cancelled();
    parallel_for(static_cast<int>(layer.size()), threads,
                 [&](int i, int) {
                   const int v = layer[i];
                   const float* x = from_desc.row(v);
                   float best = 0;
                   if (locality > 0) {
                     thread_local std::vector<float> weights;
                     weights.resize(e);
                     locality_weights(x, e, locality, weights.data());
                     image[v] = descend_to_minimum<CostPrice::kDear>(
                         to_topology, start[v], [&](int w) { return weighted_l1(x, to_desc.row(w), weights.data(), e); },
                         best);
                   } else {
                     image[v] = descend_to_minimum<CostPrice::kDear>(
                         to_topology, start[v], [&](int w) { return l1(x, to_desc.row(w), e); }, best);
                   }
                   cost[v] = best / e;
                 });
    std::vector<int> next_layer;
    for (int v : layer)
      for (const int* u = from_topology.neighbours_begin(v); u != from_topology.neighbours_end(v); ++u)
        if (start[*u] < 0) {
          start[*u] = image[v];  // layer is sorted, so the smallest matched neighbour wins
          next_layer.push_back(*u);
        }
    std::sort(next_layer.begin(), next_layer.end());
    layer.swap(next_layer);
  }
}

// Pairs whose leave-one-out d_iso against all the others exceeds `ratio` times the median
// are dropped as anchors, at most the worst `fraction` of them: a tracked map on a
// non-isometric pair has a few misplaced samples, and an anchor there would pull its
// whole neighbourhood. Order is kept, so the first E survivors are still the coarsest,
// evenly spread ones.
std::vector<SamplePair> drop_least_consistent(const PreprocessedShape& source, const PreprocessedShape& target,
                                              const std::vector<SamplePair>& pairs, double fraction, double ratio) {
  const size_t count = pairs.size();
  const size_t max_dropped = static_cast<size_t>(fraction * count);
  if (max_dropped == 0 || count < 8) return pairs;
  std::vector<double> distortion(count, 0.0);
  for (size_t p = 0; p < count; ++p) {
    const int sv = source.sample_vertex(pairs[p].source_sample);
    const int tv = image_vertex(target, pairs[p]);
    for (size_t q = 0; q < count; ++q)
      if (q != p)
        distortion[p] += std::abs(source.field(pairs[q].source_sample, sv) - target.field(pairs[q].target_sample, tv));
  }
  std::vector<size_t> order(count);
  for (size_t p = 0; p < count; ++p) order[p] = p;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return distortion[a] < distortion[b]; });
  const double threshold = ratio * distortion[order[count / 2]];
  std::vector<unsigned char> keep(count, 1);
  for (size_t r = count - 1, dropped = 0; dropped < max_dropped && distortion[order[r]] > threshold; --r, ++dropped)
    keep[order[r]] = 0;
  std::vector<SamplePair> kept;
  for (size_t p = 0; p < count; ++p)
    if (keep[p]) kept.push_back(pairs[p]);
  return kept;
}

// The dense level's anchors: their fields on both shapes, and where their images lie.
struct DenseAnchors {
  std::vector<const float*> source_fields, target_fields;
  // target_vertex: an anchor's image; field_vertex: where its target field is centred
  // (its sample until the field is recomputed at the image).
  std::vector<int> source_vertex, target_vertex, field_vertex;
  std::vector<std::vector<float>> refined_fields;  // target fields recomputed at an image
};

// The first `e` of `pairs` as anchors, where tracking left them.
DenseAnchors dense_anchors(const PreprocessedShape& source, const PreprocessedShape& target,
                           const std::vector<SamplePair>& pairs, int e) {
  DenseAnchors anchors;
  anchors.source_fields.resize(e), anchors.target_fields.resize(e);
  anchors.source_vertex.resize(e), anchors.target_vertex.resize(e), anchors.field_vertex.resize(e);
  anchors.refined_fields.resize(e);
  for (int a = 0; a < e; ++a) {
    anchors.source_fields[a] = source.field_row(pairs[a].source_sample);
    anchors.target_fields[a] = target.field_row(pairs[a].target_sample);
    anchors.source_vertex[a] = source.sample_vertex(pairs[a].source_sample);
    anchors.target_vertex[a] = image_vertex(target, pairs[a]);  // tracking's vertex-accurate image
    anchors.field_vertex[a] = target.sample_vertex(pairs[a].target_sample);
  }
  return anchors;
}

// One round of refine_anchor_images; returns how many images moved.
int move_anchor_images(const PreprocessedShape& target, const Descriptors& source_desc, DenseAnchors& anchors,
                       int threads) {
  const int e = static_cast<int>(anchors.source_vertex.size());
  const int target_n = target.mesh().num_vertices();
  const float inverse_diameter = static_cast<float>(1.0 / target.diameter());
  const MeshTopology& target_topology = target.geodesics().topology();
  std::vector<int> moved_to(e);
  parallel_for(e, threads, [&](int a, int) {
    const float* x = source_desc.row(anchors.source_vertex[a]);
    float best = 0;
    moved_to[a] = descend_to_minimum<CostPrice::kDear>(target_topology, anchors.target_vertex[a], [&](int w) {
      float sum = 0;
      for (int b = 0; b < e; ++b)
        if (b != a) sum += std::abs(x[b] - anchors.target_fields[b][w]);
      return sum;
    }, best);
  });
  std::vector<FastMarching::Workspace> workspaces(threads);
  parallel_for(e, threads, [&](int a, int worker) {
    if (moved_to[a] == anchors.field_vertex[a]) return;
    auto& ws = workspaces[worker];
    target.geodesics().compute({moved_to[a]}, ws);
    anchors.refined_fields[a].resize(target_n);
    for (int v = 0; v < target_n; ++v)
      anchors.refined_fields[a][v] = ws.distance[v] == kUnreached ? 1.f : ws.distance[v] * inverse_diameter;
  });
  int moved = 0;
  for (int a = 0; a < e; ++a) {
    if (moved_to[a] != anchors.field_vertex[a]) {
      anchors.field_vertex[a] = moved_to[a];
      anchors.target_fields[a] = anchors.refined_fields[a].data();
    }
    if (moved_to[a] != anchors.target_vertex[a]) {
      anchors.target_vertex[a] = moved_to[a];
      ++moved;
    }
  }
  return moved;
}

// Anchor images start where tracking left them (vertex-accurate where it refined them),
// but their fields are their samples'. Each round moves every anchor's image to the
// vertex that best agrees with the other anchors and recomputes the field wherever it is
// not centred on the image, so the dense level starts from vertex-accurate anchors.
void refine_anchor_images(const PreprocessedShape& target, const Descriptors& source_desc, DenseAnchors& anchors,
                          int rounds, int threads, const JobControl& control) {
  for (int round = 0; round < rounds; ++round) {
    control.check_cancelled();
    if (move_anchor_images(target, source_desc, anchors, threads) == 0) break;
  }
}

// The pairs' vertices as descent seeds, (source, target) forward, else (target, source).
std::vector<std::pair<int, int>> seeds_of(const PreprocessedShape& source, const PreprocessedShape& target,
                                          const std::vector<SamplePair>& seed_pairs, bool forward) {
  std::vector<std::pair<int, int>> seeds;
  for (const SamplePair& p : seed_pairs) {
    const int sv = source.sample_vertex(p.source_sample), tv = image_vertex(target, p);
    seeds.push_back(forward ? std::make_pair(sv, tv) : std::make_pair(tv, sv));
  }
  return seeds;
}

double mean(const std::vector<float>& values) {
  double sum = 0;
  for (float v : values) sum += v;
  return values.empty() ? 0.0 : sum / values.size();
}

}  // namespace

DenseMap compute_dense_map(const PreprocessedShape& source, const PreprocessedShape& target,
                           const std::vector<SamplePair>& all_pairs, const DenseOptions& options,
                           const JobControl& control) {
  const std::vector<SamplePair> reliable = drop_least_consistent(source, target, all_pairs, options.outlier_fraction, options.outlier_ratio);
  const std::vector<SamplePair>& pairs = reliable;
  const int e = static_cast<int>(std::min(pairs.size(), static_cast<size_t>(std::max(1, options.anchor_count))));
  const int threads = resolve_thread_count(control.threads);
  DenseAnchors anchors = dense_anchors(source, target, pairs, e);
  const Descriptors source_desc = build_descriptors(source.mesh().num_vertices(), anchors.source_fields);
  refine_anchor_images(target, source_desc, anchors, options.anchor_refinement_rounds, threads, control);
  const Descriptors target_desc = build_descriptors(target.mesh().num_vertices(), anchors.target_fields);

  // Seeds start the descent. The pairs dropped as anchors are mostly right on a thin limb
  // (a centaur's arm without seeds was reached from the torso and went to the other arm)
  // and mostly wrong on a non-isometric pair (a cat's misplaced samples pull their
  // neighbourhood), so both seed sets are tried and the forward map with the lower mean
  // d_iso, against the same anchors, is kept.
  DenseMap dense;
  const std::vector<SamplePair>* seed_pairs = &pairs;
  match_direction(source, source_desc, target, target_desc, seeds_of(source, target, pairs, true), options.locality,
                  threads, control, dense.forward, dense.forward_diso);
  if (all_pairs.size() > pairs.size()) {
    std::vector<int> image;
    std::vector<float> cost;
    match_direction(source, source_desc, target, target_desc, seeds_of(source, target, all_pairs, true),
                    options.locality, threads, control, image, cost);
    if (mean(cost) < mean(dense.forward_diso)) {
      dense.forward.swap(image);
      dense.forward_diso.swap(cost);
      seed_pairs = &all_pairs;
    }
  }
  match_direction(target, target_desc, source, source_desc, seeds_of(source, target, *seed_pairs, false),
                  options.locality, threads, control, dense.reverse, dense.reverse_diso);
  return dense;
}

}  // namespace isocorr
