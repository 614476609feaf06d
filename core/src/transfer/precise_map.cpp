#include "isocorr/transfer/precise_map.h"

#include <Eigen/SVD>
#include <algorithm>
#include <limits>
#include <string>

#include "isocorr/util/error.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

// Rings grown around a vertex at most: enough for a source about fifty times as fine as
// its target (the rings needed grow with the square root of the density ratio).
constexpr int kMaxRings = 8;

void check_map_fits(const TriangleMesh& source, const TriangleMesh& target, const std::vector<int>& map) {
  if (static_cast<int>(map.size()) != source.num_vertices())
    throw InputError("the map has " + std::to_string(map.size()) + " entries for a source of " +
                     std::to_string(source.num_vertices()) + " vertices");
  for (size_t v = 0; v < map.size(); ++v)
    if (map[v] < -1 || map[v] >= target.num_vertices())
      throw InputError("the map sends source vertex " + std::to_string(v) + " to " + std::to_string(map[v]) +
                       ", outside the target's " + std::to_string(target.num_vertices()) + " vertices");
}

// Source vertices around v, ring by ring, until their images hold kMinDistinctImages target
// vertices or kMaxRings rings are taken. `seen` is per-worker scratch, all false on entry
// and on return.
std::vector<int> neighbourhood(const MeshTopology& topology, const std::vector<int>& map, int v,
                               std::vector<char>& seen) {
  std::vector<int> taken = {v}, images;
  seen[v] = 1;
  if (map[v] >= 0) images.push_back(map[v]);
  size_t ring_begin = 0;
  for (int ring = 0; ring < kMaxRings; ++ring) {
    const size_t ring_end = taken.size();
    for (size_t i = ring_begin; i < ring_end; ++i)
      for (const int* n = topology.neighbours_begin(taken[i]); n != topology.neighbours_end(taken[i]); ++n)
        if (!seen[*n]) {
          seen[*n] = 1;
          taken.push_back(*n);
          if (map[*n] >= 0 && std::find(images.begin(), images.end(), map[*n]) == images.end())
            images.push_back(map[*n]);
        }
    ring_begin = ring_end;
    if (ring_begin == taken.size() || static_cast<int>(images.size()) >= kMinDistinctImages) break;
  }
  for (int u : taken) seen[u] = 0;
  return taken;
}

// Where v lands: the similarity transform of least squares from the neighbourhood to its
// images, applied to v (Umeyama). The image itself where the neighbourhood is degenerate.
Vec3 carried_position(const TriangleMesh& source, const TriangleMesh& target, const std::vector<int>& map, int v,
                      const std::vector<int>& around) {
  Vec3 source_mean = Vec3::Zero(), target_mean = Vec3::Zero();
  int count = 0;
  for (int u : around)
    if (map[u] >= 0) {
      source_mean += source.vertices[u];
      target_mean += target.vertices[map[u]];
      ++count;
    }
  const Vec3 fallback = target.vertices[map[v]];
  if (count < 3) return fallback;
  source_mean /= count;
  target_mean /= count;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double source_variance = 0;
  for (int u : around)
    if (map[u] >= 0) {
      const Vec3 x = source.vertices[u] - source_mean;
      covariance += (target.vertices[map[u]] - target_mean) * x.transpose();
      source_variance += x.squaredNorm();
    }
  if (!(source_variance > 0)) return fallback;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d signs(1, 1, (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1);
  const Eigen::Matrix3d rotation = svd.matrixU() * signs.asDiagonal() * svd.matrixV().transpose();
  const double scale = svd.singularValues().dot(signs) / source_variance;
  const Vec3 position = target_mean + scale * rotation * (source.vertices[v] - source_mean);
  return position.allFinite() ? position : fallback;
}

// The point nearest `position` on the triangles around `image` and its neighbours.
SurfacePoint project_near(const TriangleMesh& target, const MeshTopology& topology, int image, const Vec3& position) {
  SurfacePoint best;
  double best_distance = std::numeric_limits<double>::infinity();
  auto try_faces_of = [&](int w) {
    for (const int* f = topology.faces_begin(w); f != topology.faces_end(w); ++f) {
      const Face& face = target.faces[*f];
      const Vec3 &a = target.vertices[face[0]], &b = target.vertices[face[1]], &c = target.vertices[face[2]];
      const Eigen::Vector3d weights = nearest_on_triangle(position, a, b, c);
      const double distance = (weights[0] * a + weights[1] * b + weights[2] * c - position).squaredNorm();
      if (distance < best_distance) {
        best_distance = distance;
        best = {*f, {static_cast<float>(weights[0]), static_cast<float>(weights[1]), static_cast<float>(weights[2])}};
      }
    }
  };
  try_faces_of(image);
  for (const int* n = topology.neighbours_begin(image); n != topology.neighbours_end(image); ++n) try_faces_of(*n);
  return best;
}

}  // namespace

// Ericson, Real-Time Collision Detection 5.1.5: the Voronoi regions of corners, edges and
// face in turn.
Eigen::Vector3d nearest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double t = d1 / (d1 - d3);
    return {1 - t, t, 0};
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double t = d2 / (d2 - d6);
    return {1 - t, 0, t};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - t, t};
  }
  const double denominator = va + vb + vc;
  if (!(denominator > 0)) return {1, 0, 0};  // a degenerate triangle: its first corner
  return {va / denominator, vb / denominator, vc / denominator};
}

PreciseMap precise_map(const TriangleMesh& source, const TriangleMesh& target, const std::vector<int>& map,
                       int threads) {
  check_map_fits(source, target, map);
  const MeshTopology source_topology(source), target_topology(target);
  threads = resolve_thread_count(threads);
  std::vector<std::vector<char>> seen(threads, std::vector<char>(source.num_vertices(), 0));
  PreciseMap points(source.num_vertices());
  parallel_for(source.num_vertices(), threads, [&](int v, int worker) {
    if (map[v] < 0) return;
    const std::vector<int> around = neighbourhood(source_topology, map, v, seen[worker]);
    const Vec3 position = carried_position(source, target, map, v, around);
    points[v] = project_near(target, target_topology, map[v], position);
  });
  return points;
}

PreciseMap precise_map_in_files(const CleanMesh& source, const CleanMesh& target, const std::vector<int>& clean_map,
                                int threads) {
  const PreciseMap clean = precise_map(source.mesh, target.mesh, clean_map, threads);
  PreciseMap in_files(source.input_to_clean.size());
  for (size_t v = 0; v < in_files.size(); ++v) {
    const SurfacePoint& point = clean[source.input_to_clean[v]];
    if (point.face < 0) continue;
    const CleanMesh::InputFace& origin = target.clean_face_origins[point.face];
    in_files[v].face = origin.face;
    for (int k = 0; k < 3; ++k) in_files[v].weights[k] = point.weights[origin.clean_corner[k]];
  }
  return in_files;
}

Vec3 surface_position(const TriangleMesh& mesh, const SurfacePoint& point) {
  const Face& face = mesh.faces.at(point.face);
  return point.weights[0] * mesh.vertices[face[0]] + point.weights[1] * mesh.vertices[face[1]] +
         point.weights[2] * mesh.vertices[face[2]];
}

int nearest_corner(const TriangleMesh& mesh, const SurfacePoint& point) {
  const Face& face = mesh.faces.at(point.face);
  const auto& w = point.weights;
  return face[std::max_element(w.begin(), w.end()) - w.begin()];
}

}  // namespace isocorr
