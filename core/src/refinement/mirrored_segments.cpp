#include "mirrored_segments.h"

#include <algorithm>

#include <Eigen/Geometry>
#include <Eigen/LU>  // determinant
#include <Eigen/SparseCholesky>

#include "isocorr/matching/surface_descent.h"

namespace isocorr {
namespace {

// A ring counts as reversed when the determinant of its map between the tangent planes is
// below minus this share of an undistorted ring's: a clear reversal, not the jitter of
// nearest-vertex images (measured on SCAPE 000 -> 001: no margin left a hand's border
// inside the fold, and its continuation kept the fold).
constexpr double kReversalMargin = 0.2;
// Reversed regions smaller than this share of the vertices (at least kMinSegmentVertices)
// are nearest-vertex noise, which the polish removes by itself.
constexpr int kVerticesPerSegment = 500;
constexpr int kMinSegmentVertices = 20;
// Rings added around a reversed region so that its border lies outside the fold.
constexpr int kBorderRings = 2;
// Local-global rounds of the continuation after the first solve.
constexpr int kContinuationRounds = 5;

// Unit tangent basis (t1, t2) of the plane with this normal, t1 x t2 = normal.
void tangent_basis(const Vec3& normal, Vec3& t1, Vec3& t2) {
  const Vec3 helper = std::abs(normal.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  t1 = normal.cross(helper).normalized();
  t2 = normal.cross(t1);
}

// Whether the map reverses each vertex's ring: the sign of the least-squares linear map
// from the source's tangent plane at the vertex to the target's at its image.
std::vector<char> reversed_rings(const PreprocessedShape& source, const PreprocessedShape& target, const Rings& rings,
                                 const std::vector<int>& image, const DeformedPoints& deformed) {
  const int n = source.mesh().num_vertices();
  std::vector<char> reversed(n, 0);
  for (int v = 0; v < n; ++v) {
    Vec3 s1, s2, t1, t2;
    tangent_basis(source.normals()[v], s1, s2);
    tangent_basis(target.normals()[image[v]], t1, t2);
    Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
    double spread = 0;
    const Vec3 y = deformed.row(v).transpose();
    for (int e = rings.offsets[v]; e < rings.offsets[v + 1]; ++e) {
      const RingEdge& ring = rings.edges[e];
      const Vec3 d = y - deformed.row(ring.to).transpose();
      covariance += ring.weight * Eigen::Vector2d(ring.rest.dot(s1), ring.rest.dot(s2)) *
                    Eigen::Vector2d(d.dot(t1), d.dot(t2)).transpose();
      spread += ring.weight * ring.rest.squaredNorm();
    }
    // An undistorted ring's covariance is about spread / 2 times the identity.
    if (covariance.determinant() < -kReversalMargin * 0.25 * spread * spread) reversed[v] = 1;
  }
  return reversed;
}

// The connected sets of vertices with `member` set.
std::vector<std::vector<int>> components(const MeshTopology& topology, const std::vector<char>& member) {
  const int n = static_cast<int>(member.size());
  std::vector<char> seen(n, 0);
  std::vector<std::vector<int>> result;
  for (int v = 0; v < n; ++v) {
    if (!member[v] || seen[v]) continue;
    std::vector<int> vertices{v};
    seen[v] = 1;
    for (size_t i = 0; i < vertices.size(); ++i)
      for (const int* w = topology.neighbours_begin(vertices[i]); w != topology.neighbours_end(vertices[i]); ++w)
        if (member[*w] && !seen[*w]) seen[*w] = 1, vertices.push_back(*w);
    result.push_back(std::move(vertices));
  }
  return result;
}

// How many separate pieces the vertices just outside `region` form.
int border_pieces(const MeshTopology& topology, const std::vector<int>& region, const std::vector<char>& inside) {
  std::vector<char> border(inside.size(), 0);
  for (const int v : region)
    for (const int* w = topology.neighbours_begin(v); w != topology.neighbours_end(v); ++w)
      if (!inside[*w]) border[*w] = 1;
  return static_cast<int>(components(topology, border).size());
}

// Grows `inside` by one ring.
void grow(const MeshTopology& topology, std::vector<char>& inside) {
  std::vector<char> grown = inside;
  for (size_t v = 0; v < inside.size(); ++v)
    if (inside[v])
      for (const int* w = topology.neighbours_begin(static_cast<int>(v)); w != topology.neighbours_end(static_cast<int>(v)); ++w)
        grown[*w] = 1;
  inside.swap(grown);
}

// The as-rigid-as-possible continuation of the surroundings into the `inside` vertices:
// their rotations are first carried in from the border (each vertex, in breadth-first
// order, takes the mean of its placed neighbours'), then refitted to the positions a few
// times; the border's positions and rotations stay fixed. Returns the breadth-first
// order (border first) with each inside vertex's parent, for placing the images.
struct Continuation {
  std::vector<int> order;
  std::vector<int> parent;
  size_t border_count = 0;
};

Continuation continue_rigidly(const MeshTopology& topology, const Rings& rings, const std::vector<char>& inside,
                              DeformedPoints& deformed) {
  const int n = static_cast<int>(inside.size());
  Continuation result;
  result.parent.assign(n, -1);
  std::vector<Eigen::Matrix3d> rotation(n, Eigen::Matrix3d::Identity());
  std::vector<char> placed(n, 0);
  for (int v = 0; v < n; ++v) {
    if (inside[v]) continue;
    bool border = false;
    for (const int* w = topology.neighbours_begin(v); w != topology.neighbours_end(v); ++w) border |= inside[*w] != 0;
    if (!border) continue;
    rotation[v] = best_rotation(ring_covariance(rings, deformed, v));
    placed[v] = 1;
    result.order.push_back(v);
  }
  result.border_count = result.order.size();
  std::vector<char> queued = placed;
  for (size_t i = 0; i < result.order.size(); ++i) {
    const int v = result.order[i];
    for (const int* w = topology.neighbours_begin(v); w != topology.neighbours_end(v); ++w)
      if (inside[*w] && !queued[*w]) queued[*w] = 1, result.parent[*w] = v, result.order.push_back(*w);
  }
  for (size_t i = result.border_count; i < result.order.size(); ++i) {
    const int v = result.order[i];
    const Eigen::Quaterniond reference(rotation[result.parent[v]]);
    Eigen::Vector4d sum = Eigen::Vector4d::Zero();
    for (const int* w = topology.neighbours_begin(v); w != topology.neighbours_end(v); ++w) {
      if (!placed[*w]) continue;
      const Eigen::Vector4d q = Eigen::Quaterniond(rotation[*w]).coeffs();
      sum += q.dot(reference.coeffs()) < 0 ? Eigen::Vector4d(-q) : q;
    }
    rotation[v] = Eigen::Quaterniond(sum(3), sum(0), sum(1), sum(2)).normalized().toRotationMatrix();
    placed[v] = 1;
  }

  // sum_j w (y_v - y_j) = sum_j w (R_v + R_j) rest_vj / 2 for every inside v, border fixed.
  std::vector<int> index(n, -1), vertices;
  for (int v = 0; v < n; ++v)
    if (inside[v]) index[v] = static_cast<int>(vertices.size()), vertices.push_back(v);
  const int m = static_cast<int>(vertices.size());
  std::vector<Eigen::Triplet<double>> triplets;
  for (int i = 0; i < m; ++i)
    for (int e = rings.offsets[vertices[i]]; e < rings.offsets[vertices[i] + 1]; ++e) {
      const RingEdge& ring = rings.edges[e];
      triplets.emplace_back(i, i, ring.weight);
      if (index[ring.to] >= 0) triplets.emplace_back(i, index[ring.to], -ring.weight);
    }
  Eigen::SparseMatrix<double> matrix(m, m);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(matrix);
  if (solver.info() != Eigen::Success) return {};  // cannot happen with a border: leave the map
  Eigen::MatrixXd rhs(m, 3);
  for (int round = 0; round <= kContinuationRounds; ++round) {
    if (round > 0)
      for (const int v : vertices) rotation[v] = best_rotation(ring_covariance(rings, deformed, v));
    for (int i = 0; i < m; ++i) {
      const int v = vertices[i];
      Vec3 b = Vec3::Zero();
      for (int e = rings.offsets[v]; e < rings.offsets[v + 1]; ++e) {
        const RingEdge& ring = rings.edges[e];
        b += 0.5 * ring.weight * (rotation[v] + rotation[ring.to]) * ring.rest;
        if (index[ring.to] < 0) b += ring.weight * deformed.row(ring.to).transpose();
      }
      rhs.row(i) = b.transpose();
    }
    const Eigen::MatrixXd positions = solver.solve(rhs);
    for (int i = 0; i < m; ++i) deformed.row(vertices[i]) = positions.row(i);
  }
  return result;
}

}  // namespace

MirroredSegments unfold_mirrored_segments(const PreprocessedShape& source, const PreprocessedShape& target,
                                          const Rings& rings, std::vector<int>& image, DeformedPoints& deformed) {
  const MeshTopology& from_topology = source.geodesics().topology();
  const int n = source.mesh().num_vertices();
  MirroredSegments result;
  const std::vector<char> reversed = reversed_rings(source, target, rings, image, deformed);
  result.reversed_vertices = static_cast<int>(std::count(reversed.begin(), reversed.end(), 1));

  const size_t min_size = std::max(kMinSegmentVertices, n / kVerticesPerSegment);
  std::vector<char> inside(n, 0);
  for (const std::vector<int>& region : components(from_topology, reversed))
    if (region.size() >= min_size)
      for (const int v : region) inside[v] = 1;
  for (int ring = 0; ring < kBorderRings; ++ring) grow(from_topology, inside);
  for (const std::vector<int>& region : components(from_topology, inside)) {
    if (border_pieces(from_topology, region, inside) >= 2) {
      ++result.segments;
      continue;
    }
    for (const int v : region) inside[v] = 0;
  }
  if (result.segments == 0) return result;

  const Continuation continuation = continue_rigidly(from_topology, rings, inside, deformed);
  const TriangleMesh& to = target.mesh();
  const MeshTopology& to_topology = target.geodesics().topology();
  for (size_t i = continuation.border_count; i < continuation.order.size(); ++i) {
    const int v = continuation.order[i];
    const Vec3 position = deformed.row(v).transpose();
    auto distance = [&](int w) { return static_cast<float>((to.vertices[w] - position).squaredNorm()); };
    float squared = 0;
    image[v] = descend_to_minimum(to_topology, image[continuation.parent[v]], distance, squared);
  }
  return result;
}

}  // namespace isocorr
