#include "isocorr/matching/orientation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>

#include <Eigen/Geometry>

#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

// Signed volume of the triangle (a, b, c) against normal n.
double handedness(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n) {
  return (b - a).cross(c - a).dot(n);
}

// |sine| of the corner angle at a: how far the triangle is from flat.
double spread(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n) {
  return std::abs(handedness(a, b, c, n)) / ((b - a).norm() * (c - a).norm() + 1e-30);
}

// Triangle corners lie at these geodesic distances from the apex (fractions of the
// diameter): a few sample spacings, so one sample's error cannot swap two corners.
constexpr float kBandLow = 0.06f;
constexpr float kBandHigh = 0.12f;

}  // namespace

std::vector<PairTriangle> orientation_triangles(const PreprocessedShape& source, const std::vector<SamplePair>& pairs) {
  const int count = static_cast<int>(pairs.size());
  std::vector<PairTriangle> triangles;
  if (count < 3) return triangles;
  const auto& sp = source.mesh().vertices;
  std::vector<int> others(count);
  for (int a = 0; a < count; ++a) {
    const int sa = source.sample_vertex(pairs[a].source_sample);
    others.clear();
    // Corners at a distance band: far enough that a sample's error cannot swap them,
    // near enough that the triangle still lies roughly in the tangent plane at a.
    for (int o = 0; o < count; ++o) {
      if (o == a) continue;
      const float d = source.sample_field(pairs[a].source_sample, pairs[o].source_sample);
      if (d >= kBandLow && d <= kBandHigh) others.push_back(o);
    }
    if (others.size() < 2) continue;
    const Vec3& n = source.normals()[sa];
    int b = -1, c = -1;
    double best_spread = 0;
    for (size_t i = 0; i < others.size(); ++i)
      for (size_t j = i + 1; j < others.size(); ++j) {
        const int sb = source.sample_vertex(pairs[others[i]].source_sample);
        const int sc = source.sample_vertex(pairs[others[j]].source_sample);
        const double s = spread(sp[sa], sp[sb], sp[sc], n);
        if (s > best_spread) best_spread = s, b = others[i], c = others[j];
      }
    if (c < 0 || best_spread < 0.2) continue;
    const int sb = source.sample_vertex(pairs[b].source_sample), sc = source.sample_vertex(pairs[c].source_sample);
    triangles.push_back({a, b, c, handedness(sp[sa], sp[sb], sp[sc], n) > 0});
  }
  return triangles;
}

double orientation_agreement(const PreprocessedShape& target, const std::vector<SamplePair>& pairs,
                             const std::vector<PairTriangle>& triangles) {
  if (pairs.size() < 3) return 0.5;
  const auto& tp = target.mesh().vertices;
  int agree = 0, total = 0;
  for (const PairTriangle& t : triangles) {
    const int ta = image_vertex(target, pairs[t.a]), tb = image_vertex(target, pairs[t.b]),
              tc = image_vertex(target, pairs[t.c]);
    const double target_sign = handedness(tp[ta], tp[tb], tp[tc], target.normals()[ta]);
    if (target_sign == 0) continue;
    ++total;
    if (t.positive == (target_sign > 0)) ++agree;
  }
  return total ? static_cast<double>(agree) / total : 0.5;
}

double orientation_agreement(const PreprocessedShape& source, const PreprocessedShape& target,
                             const std::vector<SamplePair>& pairs) {
  return orientation_agreement(target, pairs, orientation_triangles(source, pairs));
}

std::vector<GuardCorners> guard_corners(const PreprocessedShape& source, const std::vector<SamplePair>& matched,
                                        int source_vertex, float min_distance) {
  constexpr size_t kNearest = 8;      // corners are drawn from this many nearest matched samples
  constexpr size_t kTriangles = 3;    // best-spread triangles kept (an odd number: a clear vote)
  constexpr double kMinSpread = 0.3;  // |sine| of the corner angle; flatter triangles are unstable
  std::vector<std::pair<float, int>> near;
  for (int i = 0; i < static_cast<int>(matched.size()); ++i) {
    const float d = source.field(matched[i].source_sample, source_vertex);
    if (d >= min_distance) near.push_back({d, i});
  }
  const size_t count = std::min(near.size(), kNearest);
  std::partial_sort(near.begin(), near.begin() + count, near.end());
  const auto& sp = source.mesh().vertices;
  const Vec3& a = sp[source_vertex];
  const Vec3& n = source.normals()[source_vertex];
  struct Candidate {
    double spread;
    GuardCorners corners;
  };
  std::vector<Candidate> candidates;
  for (size_t i = 0; i < count; ++i)
    for (size_t j = i + 1; j < count; ++j) {
      const Vec3& b = sp[source.sample_vertex(matched[near[i].second].source_sample)];
      const Vec3& c = sp[source.sample_vertex(matched[near[j].second].source_sample)];
      const double s = spread(a, b, c, n);
      if (s >= kMinSpread) candidates.push_back({s, {near[i].second, near[j].second, handedness(a, b, c, n) > 0}});
    }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.spread > y.spread; });
  std::vector<GuardCorners> corners;
  for (size_t k = 0; k < std::min(candidates.size(), kTriangles); ++k) corners.push_back(candidates[k].corners);
  return corners;
}

HandednessGuard::HandednessGuard(const PreprocessedShape& target, const std::vector<SamplePair>& matched,
                                 const std::vector<GuardCorners>& corners)
    : target_(target) {
  for (const GuardCorners& c : corners)
    triangles_.push_back({image_vertex(target, matched[c.b]), image_vertex(target, matched[c.c]), c.positive});
}

bool HandednessGuard::accepts(int target_vertex) const {
  const auto& tp = target_.mesh().vertices;
  const Vec3& n = target_.normals()[target_vertex];
  int agree = 0;
  for (const Triangle& t : triangles_)
    agree += (handedness(tp[target_vertex], tp[t.target_b], tp[t.target_c], n) > 0) == t.positive;
  return 2 * agree >= static_cast<int>(triangles_.size());
}

double dense_orientation_agreement(const TriangleMesh& source, const std::vector<Vec3>& source_normals,
                                   const TriangleMesh& target, const std::vector<Vec3>& target_normals,
                                   const std::vector<int>& target_of) {
  int agree = 0, total = 0;
  for (const Face& f : source.faces) {
    const int a = target_of[f[0]], b = target_of[f[1]], c = target_of[f[2]];
    if (a == b || b == c || a == c || a < 0 || b < 0 || c < 0) continue;
    const Vec3 ns = source_normals[f[0]] + source_normals[f[1]] + source_normals[f[2]];
    const Vec3 nt = target_normals[a] + target_normals[b] + target_normals[c];
    const double s = handedness(source.vertices[f[0]], source.vertices[f[1]], source.vertices[f[2]], ns);
    const double t = handedness(target.vertices[a], target.vertices[b], target.vertices[c], nt);
    if (s == 0 || t == 0) continue;
    ++total;
    if ((s > 0) == (t > 0)) ++agree;
  }
  return total ? static_cast<double>(agree) / total : 0.5;
}

namespace {

// Two unit vectors spanning the plane orthogonal to n.
std::pair<Vec3, Vec3> tangent_frame(const Vec3& n) {
  const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  const Vec3 u = n.cross(helper).normalized();
  return {u, n.cross(u)};
}

// Vertices within `radius` of `centre` along edges, by a Dijkstra that only touches them.
// `distance` holds +inf for every vertex on entry and on exit.
void gather_neighbourhood(const TriangleMesh& mesh, const MeshTopology& topology, int centre, double radius,
                          std::vector<double>& distance, std::vector<int>& reached) {
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap;
  reached.clear();
  distance[centre] = 0;
  reached.push_back(centre);
  heap.push({0.0, centre});
  while (!heap.empty()) {
    const auto [d, v] = heap.top();
    heap.pop();
    if (d > distance[v]) continue;
    for (const int* w = topology.neighbours_begin(v); w != topology.neighbours_end(v); ++w) {
      const double candidate = d + (mesh.vertices[*w] - mesh.vertices[v]).norm();
      if (candidate > radius || candidate >= distance[*w]) continue;
      if (distance[*w] == std::numeric_limits<double>::infinity()) reached.push_back(*w);
      distance[*w] = candidate;
      heap.push({candidate, *w});
    }
  }
}

// +1 per centre where the neighbourhood keeps handedness, -1 where the map reverses it, 0
// where the fit is degenerate.
std::vector<signed char> neighbourhood_handedness(const TriangleMesh& source, const std::vector<Vec3>& source_normals,
                                                  const MeshTopology& source_topology, const TriangleMesh& target,
                                                  const std::vector<Vec3>& target_normals,
                                                  const std::vector<int>& target_of, const std::vector<int>& centres,
                                                  double radius, int threads) {
  threads = resolve_thread_count(threads);
  const int count = static_cast<int>(centres.size());
  struct Workspace {
    std::vector<double> distance;
    std::vector<int> reached;
  };
  std::vector<Workspace> workspaces(threads);
  for (auto& ws : workspaces) ws.distance.assign(source.num_vertices(), std::numeric_limits<double>::infinity());
  std::vector<signed char> sign(count, 0);
  parallel_for(count, threads, [&](int i, int worker) {
    Workspace& ws = workspaces[worker];
    const int v = centres[i];
    gather_neighbourhood(source, source_topology, v, radius, ws.distance, ws.reached);
    const auto [su, sv] = tangent_frame(source_normals[v]);
    const int image = target_of[v];
    const auto [tu, tv] = tangent_frame(target_normals[image]);
    // Cross-covariance of source and image offsets: its determinant has the sign of the
    // least-squares differential's (the source covariance's determinant is positive).
    Eigen::Matrix2d cross = Eigen::Matrix2d::Zero();
    for (const int w : ws.reached) {
      const Vec3 ds = source.vertices[w] - source.vertices[v];
      const Vec3 dt = target.vertices[target_of[w]] - target.vertices[image];
      const Eigen::Vector2d p(ds.dot(su), ds.dot(sv)), q(dt.dot(tu), dt.dot(tv));
      cross += q * p.transpose();
      ws.distance[w] = std::numeric_limits<double>::infinity();
    }
    const double det = cross.determinant();
    const double scale = cross.squaredNorm();
    if (scale > 0 && std::abs(det) > 1e-6 * scale) sign[i] = det > 0 ? 1 : -1;
  });
  return sign;
}

}  // namespace

double neighbourhood_orientation_agreement(const TriangleMesh& source, const std::vector<Vec3>& source_normals,
                                           const MeshTopology& source_topology, const TriangleMesh& target,
                                           const std::vector<Vec3>& target_normals,
                                           const std::vector<int>& target_of, const std::vector<int>& centres,
                                           double radius, int threads) {
  const std::vector<signed char> sign = neighbourhood_handedness(source, source_normals, source_topology, target,
                                                                 target_normals, target_of, centres, radius, threads);
  int agree = 0, total = 0;
  for (const signed char s : sign) total += s != 0, agree += s > 0;
  return total ? static_cast<double>(agree) / total : 0.5;
}

}  // namespace isocorr
