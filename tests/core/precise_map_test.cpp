// Precise maps: exact on an exact map, and finer than the vertex map between resolutions.
#include "isocorr/transfer/precise_map.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

// `coarse` with a vertex on every edge, at 0.4 of its length from a random end: the coarse
// vertices keep their numbers, so the fine mesh's true points on the coarse one are known.
struct Refined {
  TriangleMesh fine;
  std::vector<Vec3> true_points;  // per fine vertex, its place on the coarse surface
};

Refined split_edges_off_centre(const TriangleMesh& coarse, uint32_t seed) {
  Refined out{coarse, coarse.vertices};
  out.fine.faces.clear();
  std::mt19937 random(seed);
  std::map<std::pair<int, int>, int> edge_vertex;
  auto split = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    auto found = edge_vertex.find(key);
    if (found != edge_vertex.end()) return found->second;
    const double t = random() % 2 ? 0.4 : 0.6;
    const Vec3 point = (1 - t) * coarse.vertices[a] + t * coarse.vertices[b];
    out.fine.vertices.push_back(point);
    out.true_points.push_back(point);
    return edge_vertex[key] = out.fine.num_vertices() - 1;
  };
  for (const Face& f : coarse.faces) {
    const int ab = split(f[0], f[1]), bc = split(f[1], f[2]), ca = split(f[2], f[0]);
    out.fine.faces.push_back({f[0], ab, ca});
    out.fine.faces.push_back({ab, f[1], bc});
    out.fine.faces.push_back({ca, bc, f[2]});
    out.fine.faces.push_back({ab, bc, ca});
  }
  return out;
}

std::vector<int> nearest_vertices(const std::vector<Vec3>& points, const TriangleMesh& mesh) {
  std::vector<int> nearest(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    double best = 1e300;
    for (int v = 0; v < mesh.num_vertices(); ++v)
      if ((mesh.vertices[v] - points[i]).squaredNorm() < best) best = (mesh.vertices[v] - points[i]).squaredNorm(), nearest[i] = v;
  }
  return nearest;
}

TEST(PreciseMap, AnExactMapLandsEveryVertexOnItsImage) {
  const TriangleMesh blob = limbed_blob(2);
  const RenumberedCopy copy = rotated_scaled_renumbered(blob, 2.5, 7);
  const PreciseMap points = precise_map(blob, copy.mesh, copy.permutation, 2);
  ASSERT_EQ(points.size(), blob.vertices.size());
  for (int v = 0; v < blob.num_vertices(); ++v) {
    const Vec3 image = copy.mesh.vertices[copy.permutation[v]];
    EXPECT_LT((surface_position(copy.mesh, points[v]) - image).norm(), 1e-6) << "vertex " << v;
    EXPECT_EQ(nearest_corner(copy.mesh, points[v]), copy.permutation[v]);
  }
}

TEST(PreciseMap, FromAFinerMeshItPlacesVerticesBetweenTheCoarseOnes) {
  const TriangleMesh coarse = limbed_blob(2);
  const Refined refined = split_edges_off_centre(coarse, 3);
  const std::vector<int> vertex_map = nearest_vertices(refined.fine.vertices, coarse);
  const PreciseMap points = precise_map(refined.fine, coarse, vertex_map);
  double vertex_error = 0, point_error = 0;
  for (int v = 0; v < refined.fine.num_vertices(); ++v) {
    vertex_error += (coarse.vertices[vertex_map[v]] - refined.true_points[v]).norm();
    point_error += (surface_position(coarse, points[v]) - refined.true_points[v]).norm();
    const auto& w = points[v].weights;
    EXPECT_NEAR(w[0] + w[1] + w[2], 1.0, 1e-5);
    EXPECT_GE(std::min({w[0], w[1], w[2]}), 0.0f);
  }
  // The vertex map is off by about 0.4 of an edge at every split vertex.
  EXPECT_LT(point_error, 0.25 * vertex_error) << "vertex map " << vertex_error << ", precise " << point_error;
}

TEST(PreciseMap, UnmatchedVerticesStayUnmatched) {
  const TriangleMesh sphere = icosphere(2);
  std::vector<int> map(sphere.num_vertices());
  for (int v = 0; v < sphere.num_vertices(); ++v) map[v] = v;
  map[5] = -1;
  const PreciseMap points = precise_map(sphere, sphere, map);
  EXPECT_EQ(points[5].face, -1);
  EXPECT_GE(points[6].face, 0);
}

TEST(PreciseMap, AMapThatDoesNotFitIsAnInputError) {
  const TriangleMesh sphere = icosphere(1);
  std::vector<int> short_map(sphere.num_vertices() - 1, 0);
  EXPECT_THROW(precise_map(sphere, sphere, short_map), InputError);
  std::vector<int> outside(sphere.num_vertices(), 0);
  outside[3] = sphere.num_vertices();
  EXPECT_THROW(precise_map(sphere, sphere, outside), InputError);
}

}  // namespace
}  // namespace isocorr
