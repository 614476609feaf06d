// Ground-truth scores (D_grd, Kim et al. curve, flip detection) and SHREC'20 coverage.
#include "isocorr/eval/metrics.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include "isocorr/util/error.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

constexpr double kMirrorError = 0.1;  // a point counts as flipped only beyond this error (x diameter)
constexpr double kFarError = 0.2;     // "far" points (x diameter)
constexpr double kFlipFreeMean = 0.1;
constexpr double kFlipFreeFraction = 0.05;

void check_vertex(int v, int count, const char* what) {
  if (v < 0 || v >= count)
    throw InputError(std::string(what) + " " + std::to_string(v) + " is not a vertex of the target (" +
                     std::to_string(count) + " vertices)");
}

// Labels every vertex with the index of its nearest seed (-1 if no seed reaches it).
// Edge Dijkstra, not fast marching: the labels only decide which cell a vertex falls in,
// and fast marching has no multi-source labelling; the ~8% metric bias shifts cell
// boundaries by a fraction of an edge, which barely moves the covered area.
std::vector<int> voronoi_labels(const TriangleMesh& mesh, const MeshTopology& topology,
                                const std::vector<int>& seeds) {
  const int n = mesh.num_vertices();
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<int> label(n, -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap;
  for (int s = 0; s < static_cast<int>(seeds.size()); ++s) {
    if (dist[seeds[s]] == 0) continue;  // a repeated seed keeps its first label
    dist[seeds[s]] = 0;
    label[seeds[s]] = s;
    heap.push({0.0, seeds[s]});
  }
  while (!heap.empty()) {
    const auto [d, v] = heap.top();
    heap.pop();
    if (d > dist[v]) continue;
    for (const int* w = topology.neighbours_begin(v); w != topology.neighbours_end(v); ++w) {
      const double candidate = d + (mesh.vertices[*w] - mesh.vertices[v]).norm();
      if (candidate < dist[*w]) {
        dist[*w] = candidate;
        label[*w] = label[v];
        heap.push({candidate, *w});
      }
    }
  }
  return label;
}

// The geodesic distance from a point on the target to `truth_vertex`: the corners'
// distances, interpolated by the point's weights. `vertex_error` is the distance from the
// point's nearest corner, which bounds the search: no corner is farther than it plus two
// of the face's edges.
double point_error(const TriangleMesh& target, const FastMarching& geodesics, const SurfacePoint& point,
                   int truth_vertex, double vertex_error, FastMarching::Workspace& ws) {
  const Face& face = target.faces.at(point.face);
  double longest_edge = 0;
  for (int j = 0; j < 3; ++j)
    longest_edge = std::max(longest_edge, (target.vertices[face[j]] - target.vertices[face[(j + 1) % 3]]).norm());
  geodesics.compute({truth_vertex}, ws, static_cast<float>(vertex_error + 2.5 * longest_edge));
  double error = 0;
  for (int j = 0; j < 3; ++j) {
    const float d = ws.distance[face[j]];
    if (d == kUnreached) return vertex_error;
    error += point.weights[j] * d;
  }
  return error;
}

}  // namespace

GroundTruthScore score_against_ground_truth(const TriangleMesh& target, const FastMarching& target_geodesics,
                                            double target_diameter, const std::vector<int>& forward,
                                            const GroundTruth& truth, const EvaluationOptions& options) {
  const int nv = target.num_vertices();
  if (target_geodesics.mesh().num_vertices() != nv)
    throw InputError("the geodesics were built for a different mesh than the target");
  if (!(target_diameter > 0)) throw InputError("the target diameter must be positive");
  if (truth.source.size() != truth.target.size() ||
      (!truth.mirrored_target.empty() && truth.mirrored_target.size() != truth.target.size()))
    throw InputError("ground truth lists of different lengths");
  const double sqrt_area = std::sqrt(total_area(target));
  if (!(sqrt_area > 0)) throw InputError("the target mesh has zero area");
  const bool has_mirror = !truth.mirrored_target.empty();
  if (options.precise) {
    if (options.precise->size() != forward.size())
      throw InputError("the precise map has " + std::to_string(options.precise->size()) + " points for " +
                       std::to_string(forward.size()) + " source vertices");
    for (const SurfacePoint& point : *options.precise)
      if (point.face < -1 || point.face >= target.num_faces())
        throw InputError("the precise map names face " + std::to_string(point.face) + ", not a face of the target (" +
                         std::to_string(target.num_faces()) + " faces)");
  }

  GroundTruthScore score;
  for (int j = 0; j <= 100; ++j) score.kim_thresholds.push_back(0.25 * j / 100.0);
  score.flip_rule = has_mirror
      ? "flip-free: mean error < 0.1 diameter and <= 5% of points nearer their mirror image by more than 0.1 diameter"
      : "flip-free (no symmetry GT): mean error < 0.1 diameter and <= 5% of points farther than 0.2 diameter";

  // Evenly strided, deterministic subset of the pairs.
  const int total = static_cast<int>(truth.source.size());
  const int count = options.max_points > 0 ? std::min(total, options.max_points) : total;
  std::vector<int> chosen(count);
  for (int i = 0; i < count; ++i) chosen[i] = static_cast<int>(static_cast<long long>(i) * total / count);
  for (int k : chosen) {
    const int s = truth.source[k];
    if (s < 0 || s >= static_cast<int>(forward.size()))
      throw InputError("ground-truth source vertex " + std::to_string(s) + " has no entry in the map (" +
                       std::to_string(forward.size()) + " entries)");
    check_vertex(forward[s], nv, "mapped vertex");
    check_vertex(truth.target[k], nv, "ground-truth target vertex");
    if (has_mirror && truth.mirrored_target[k] >= 0) check_vertex(truth.mirrored_target[k], nv, "mirrored vertex");
  }
  score.evaluated = count;
  score.kim_curve.assign(score.kim_thresholds.size(), 0.0);
  if (count == 0) return score;

  // Geodesic error per point, in absolute units; nearer-mirror flag per point.
  std::vector<double> error(count);
  std::vector<char> nearer_mirror(count, 0);
  const int threads = resolve_thread_count(options.threads);
  std::vector<FastMarching::Workspace> workspaces(std::max(1, std::min(threads, count)));
  parallel_for(count, threads, [&](int i, int worker) {
    const int k = chosen[i];
    const int truth_vertex = truth.target[k];
    FastMarching::Workspace& ws = workspaces[worker];
    target_geodesics.compute({forward[truth.source[k]]}, ws, kUnreached, truth_vertex);
    // Another connected component: count it as the largest possible error.
    const float d = ws.distance[truth_vertex];
    error[i] = d == kUnreached ? target_diameter : d;
    const int mirror = has_mirror ? truth.mirrored_target[k] : -1;
    nearer_mirror[i] = mirror >= 0 && ws.distance[mirror] != kUnreached && ws.distance[mirror] < error[i];
    if (options.precise && d != kUnreached && (*options.precise)[truth.source[k]].face >= 0)
      error[i] = point_error(target, target_geodesics, (*options.precise)[truth.source[k]], truth_vertex, error[i], ws);
  });

  int mirrored = 0, far = 0;
  for (int i = 0; i < count; ++i) {
    const double e = error[i] / target_diameter, kim = error[i] / sqrt_area;
    score.mean_error += e;
    score.max_error = std::max(score.max_error, e);
    score.mean_kim_error += kim;
    for (size_t j = 0; j < score.kim_thresholds.size(); ++j)
      if (kim <= score.kim_thresholds[j]) score.kim_curve[j] += 1;
    mirrored += nearer_mirror[i] && e > kMirrorError;
    far += e > kFarError;
  }
  score.mean_error /= count;
  score.mean_kim_error /= count;
  for (double& c : score.kim_curve) c /= count;
  for (double c : score.kim_curve) score.kim_auc += c;
  score.kim_auc /= static_cast<double>(score.kim_curve.size());
  score.far_fraction = static_cast<double>(far) / count;
  if (has_mirror) score.mirrored_fraction = static_cast<double>(mirrored) / count;
  score.point_sources.resize(count);
  score.point_errors.resize(count);
  for (int i = 0; i < count; ++i) {
    score.point_sources[i] = truth.source[chosen[i]];
    score.point_errors[i] = error[i] / target_diameter;
  }
  score.point_nearer_mirror = std::move(nearer_mirror);
  score.flip_free = score.mean_error < kFlipFreeMean &&
                    (has_mirror ? score.mirrored_fraction : score.far_fraction) <= kFlipFreeFraction;
  return score;
}

namespace {

// Up to `count` farthest-point seeds on the target (fewer when every vertex is one).
std::vector<int> farthest_point_seeds(const FastMarching& target_geodesics, int nv, int count) {
  FastMarching::Workspace ws;
  target_geodesics.compute({0}, ws);
  int first = 0;
  for (int v = 0; v < nv; ++v)
    if (ws.distance[v] != kUnreached && ws.distance[v] > ws.distance[first]) first = v;
  std::vector<int> seeds{first};
  std::vector<float> nearest(nv, kUnreached);
  while (true) {
    // Only vertices nearer than the current farthest one can change: cut the field there.
    const float radius = seeds.size() == 1 ? kUnreached : nearest[seeds.back()];
    target_geodesics.compute({seeds.back()}, ws, radius);
    for (int v : ws.touched) nearest[v] = std::min(nearest[v], ws.distance[v]);
    if (static_cast<int>(seeds.size()) == count) break;
    // Unreached vertices (other components) come first, as infinitely far.
    int next = 0;
    for (int v = 1; v < nv; ++v)
      if (nearest[v] > nearest[next]) next = v;
    if (nearest[next] == 0) break;  // every vertex is a seed
    seeds.push_back(next);
  }
  return seeds;
}

// Which of the `cells` Voronoi cells (labels per vertex) hold one of `images`.
std::vector<char> cells_hit(const std::vector<int>& label, int cells, const std::vector<int>& images) {
  std::vector<char> hit(cells, 0);
  for (int v : images)
    if (label[v] >= 0) hit[label[v]] = 1;
  return hit;
}

}  // namespace

std::vector<double> coverage(const TriangleMesh& target, const FastMarching& target_geodesics,
                             const std::vector<int>& forward, const std::vector<int>& seed_counts) {
  const int nv = target.num_vertices();
  std::vector<double> result(seed_counts.size(), 0.0);
  if (nv == 0 || seed_counts.empty()) return result;
  for (int v : forward) check_vertex(v, nv, "mapped vertex");
  const int largest = std::min(nv, *std::max_element(seed_counts.begin(), seed_counts.end()));
  if (largest <= 0) return result;
  // Farthest-point seeds for the largest count; every smaller count uses a prefix, which is
  // what FPS would have chosen for it anyway.
  const std::vector<int> seeds = farthest_point_seeds(target_geodesics, nv, largest);

  const std::vector<double> areas = vertex_areas(target);
  double total = 0;
  for (double a : areas) total += a;
  if (!(total > 0)) return result;
  for (size_t c = 0; c < seed_counts.size(); ++c) {
    const int n = std::min(seed_counts[c], static_cast<int>(seeds.size()));
    if (n <= 0) continue;
    const std::vector<int> label =
        voronoi_labels(target, target_geodesics.topology(), std::vector<int>(seeds.begin(), seeds.begin() + n));
    const std::vector<char> hit = cells_hit(label, n, forward);
    double covered = 0;
    for (int v = 0; v < nv; ++v)
      if (label[v] >= 0 && hit[label[v]]) covered += areas[v];
    result[c] = covered / total;
  }
  return result;
}

double coverage_of_true_image(const TriangleMesh& target, const FastMarching& target_geodesics,
                              const std::vector<int>& forward, const std::vector<int>& true_images, int seed_count) {
  const int nv = target.num_vertices();
  if (nv == 0 || seed_count <= 0) return 0;
  for (int v : forward) check_vertex(v, nv, "mapped vertex");
  for (int v : true_images) check_vertex(v, nv, "true image");
  const std::vector<int> seeds = farthest_point_seeds(target_geodesics, nv, std::min(nv, seed_count));
  const std::vector<int> label = voronoi_labels(target, target_geodesics.topology(), seeds);
  const int cells = static_cast<int>(seeds.size());
  const std::vector<char> reached = cells_hit(label, cells, forward), owed = cells_hit(label, cells, true_images);
  const std::vector<double> areas = vertex_areas(target);
  double covered = 0, total = 0;
  for (int v = 0; v < nv; ++v)
    if (label[v] >= 0 && owed[label[v]]) {
      total += areas[v];
      if (reached[label[v]]) covered += areas[v];
    }
  return total > 0 ? covered / total : 0;
}

}  // namespace isocorr
