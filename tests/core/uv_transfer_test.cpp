// UV transfer through a precise map: exact on a renumbered, rotated copy (seams included),
// barycentric inside faces, and the seam rule across islands.
#include "isocorr/transfer/uv_transfer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

using Uv = std::array<double, 2>;

constexpr double kTolerance = 1e-6;  // the map's weights are floats

// UVs of a sphere laid out as an artist might: a cylindrical band (|z| of the face's centre
// below 0.5) whose wrap-around seam cuts it open, and two planar caps, each in its own part of
// the texture. Seam vertices get one vt per side; the band and the caps are three islands.
// Materials: "band" and "cap".
TexturedMesh band_and_caps(const TriangleMesh& mesh) {
  TexturedMesh textured{mesh, {}};
  CornerAttributes& c = textured.corners;
  c.material_library = "sphere.mtl";
  c.materials = {"band", "cap"};
  // Each vertex's UV in each part, computed once so that equal UVs are equal bit for bit.
  std::vector<std::array<Uv, 3>> parts;
  for (const Vec3& p : mesh.vertices)
    parts.push_back({Uv{std::atan2(p.y(), p.x()) / (2 * std::numbers::pi) + 0.5, 0.25 + 0.24 * p.z()},
                     Uv{0.25 + 0.2 * p.x(), 0.75 + 0.2 * p.y()}, Uv{0.75 + 0.2 * p.x(), 0.75 + 0.2 * p.y()}});
  std::map<std::tuple<int, double, double>, int> numbers;
  for (const Face& face : mesh.faces) {
    const Vec3 centre = (mesh.vertices[face[0]] + mesh.vertices[face[1]] + mesh.vertices[face[2]]) / 3;
    const int part = centre.z() > 0.5 ? 1 : centre.z() < -0.5 ? 2 : 0;
    std::array<Uv, 3> uvs;
    for (int k = 0; k < 3; ++k) uvs[k] = parts[face[k]][part];
    if (part == 0) {
      // A face across the wrap-around takes its small u's past 1, as an unwrapped band does.
      const auto [low, high] = std::minmax({uvs[0][0], uvs[1][0], uvs[2][0]});
      if (high - low > 0.5)
        for (Uv& uv : uvs)
          if (uv[0] < 0.5) uv[0] += 1;
    }
    std::array<int, 3> corners;
    for (int k = 0; k < 3; ++k) {
      const auto [it, added] = numbers.try_emplace({face[k], uvs[k][0], uvs[k][1]}, static_cast<int>(c.uvs.size()));
      if (added) c.uvs.push_back(uvs[k]);
      corners[k] = it->second;
    }
    c.face_uvs.push_back(corners);
    c.face_materials.push_back(part == 0 ? 0 : 1);
  }
  return textured;
}

double extent(const CornerAttributes& corners, int face, int axis) {
  const auto& f = corners.face_uvs[face];
  const auto [low, high] = std::minmax({corners.uvs[f[0]][axis], corners.uvs[f[1]][axis], corners.uvs[f[2]][axis]});
  return high - low;
}

// The point of `mesh` at target vertex v: a face around v (the `choice`-th, so that vertices
// on a seam land on either side), weight 1 on v's corner.
SurfacePoint at_vertex(const TriangleMesh& mesh, const std::vector<std::vector<int>>& faces_of, int v, int choice) {
  const int face = faces_of[v][choice % faces_of[v].size()];
  SurfacePoint point{face, {0, 0, 0}};
  for (int k = 0; k < 3; ++k)
    if (mesh.faces[face][k] == v) point.weights[k] = 1;
  return point;
}

std::vector<std::vector<int>> faces_of_vertices(const TriangleMesh& mesh) {
  std::vector<std::vector<int>> faces_of(mesh.vertices.size());
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int v : mesh.faces[f]) faces_of[v].push_back(f);
  return faces_of;
}

TEST(UvTransfer, TheAtlasHasThreeIslands) {
  const TexturedMesh sphere = band_and_caps(icosphere(3));
  const std::vector<int> islands = uv_islands(sphere.mesh, sphere.corners);
  EXPECT_EQ(*std::max_element(islands.begin(), islands.end()), 2);
  EXPECT_EQ(islands[0], 0);
  // Written with one vt per corner, as some exporters do, the islands are the same.
  CornerAttributes per_corner;
  for (const auto& corners : sphere.corners.face_uvs) {
    const int first = static_cast<int>(per_corner.uvs.size());
    for (int index : corners) per_corner.uvs.push_back(sphere.corners.uvs[index]);
    per_corner.face_uvs.push_back({first, first + 1, first + 2});
  }
  EXPECT_EQ(uv_islands(sphere.mesh, per_corner), islands);
}

TEST(UvTransfer, ARenumberedRotatedCopyGetsTheTrueUvsAcrossSeams) {
  const TexturedMesh target = band_and_caps(icosphere(3));
  const RenumberedCopy copy = rotated_scaled_renumbered(target.mesh, 1.0, 7);
  const TriangleMesh& source = copy.mesh;
  std::vector<int> original(source.vertices.size());  // source vertex -> target vertex
  for (size_t i = 0; i < copy.permutation.size(); ++i) original[copy.permutation[i]] = static_cast<int>(i);

  const std::vector<std::vector<int>> faces_of = faces_of_vertices(target.mesh);
  PreciseMap map(source.vertices.size());
  for (int v = 0; v < source.num_vertices(); ++v) map[v] = at_vertex(target.mesh, faces_of, original[v], v);

  // The truth: the UVs of the target face with the same vertices.
  std::map<std::array<int, 3>, int> face_of_corners;
  for (int f = 0; f < target.mesh.num_faces(); ++f) {
    std::array<int, 3> key = target.mesh.faces[f];
    std::sort(key.begin(), key.end());
    face_of_corners[key] = f;
  }

  const CornerAttributes uvs = transfer_uvs(source, target, map);
  check_corner_attributes(source, uvs);
  ASSERT_EQ(uvs.face_uvs.size(), source.faces.size());
  EXPECT_EQ(uvs.materials, target.corners.materials);
  EXPECT_EQ(uvs.material_library, "sphere.mtl");
  int seam_triangles = 0;
  for (int f = 0; f < source.num_faces(); ++f) {
    std::array<int, 3> key;
    for (int k = 0; k < 3; ++k) key[k] = original[source.faces[f][k]];
    std::sort(key.begin(), key.end());
    const int truth = face_of_corners.at(key);
    // Each vertex's own landing UV, mixed from either side of a seam, would tear the texture.
    double landed_low = 1e9, landed_high = -1e9;
    for (int k = 0; k < 3; ++k) {
      const int v = source.faces[f][k];
      const int corner = int(std::find(target.mesh.faces[truth].begin(), target.mesh.faces[truth].end(), original[v]) -
                             target.mesh.faces[truth].begin());
      const Uv expected = target.corners.uvs[target.corners.face_uvs[truth][corner]];
      const Uv got = uvs.uvs[uvs.face_uvs[f][k]];
      EXPECT_NEAR(got[0], expected[0], kTolerance) << "face " << f << " corner " << k;
      EXPECT_NEAR(got[1], expected[1], kTolerance) << "face " << f << " corner " << k;
      const SurfacePoint& p = map[v];
      const int own = int(std::max_element(p.weights.begin(), p.weights.end()) - p.weights.begin());
      const Uv landed = target.corners.uvs[target.corners.face_uvs[p.face][own]];
      landed_low = std::min(landed_low, landed[0]), landed_high = std::max(landed_high, landed[0]);
    }
    seam_triangles += landed_high - landed_low > 0.5;
    EXPECT_LT(extent(uvs, f, 0), 0.5) << "face " << f;
    EXPECT_LT(extent(uvs, f, 1), 0.5) << "face " << f;
    EXPECT_EQ(uvs.face_materials[f], target.corners.face_materials[truth]) << "face " << f;
  }
  EXPECT_GT(seam_triangles, 5);  // the test reaches the seams
  // One vt per vertex and side of a seam, as in the target.
  EXPECT_EQ(uvs.uvs.size(), target.corners.uvs.size());
}

// A flat grid whose UVs are its coordinates scaled, so that any point's true UV is known.
TexturedMesh planar_grid() {
  TexturedMesh textured{grid(6, 5), {}};
  for (const Vec3& p : textured.mesh.vertices) textured.corners.uvs.push_back({p.x() / 5, p.y() / 4});
  for (const Face& f : textured.mesh.faces) textured.corners.face_uvs.push_back(f);
  return textured;
}

Vec3 position(const TriangleMesh& mesh, const SurfacePoint& point) {
  const Face& f = mesh.faces[point.face];
  return point.weights[0] * mesh.vertices[f[0]] + point.weights[1] * mesh.vertices[f[1]] +
         point.weights[2] * mesh.vertices[f[2]];
}

TEST(UvTransfer, PointsInsideFacesMixTheirCornersUvs) {
  const TexturedMesh target = planar_grid();
  // The source is the grid again, each vertex moved into a face around it: half its own
  // corner and a quarter of each other, or an edge's midpoint.
  const std::vector<std::vector<int>> faces_of = faces_of_vertices(target.mesh);
  PreciseMap map(target.mesh.vertices.size());
  for (int v = 0; v < target.mesh.num_vertices(); ++v) {
    map[v] = at_vertex(target.mesh, faces_of, v, v);
    const int own = int(std::find(map[v].weights.begin(), map[v].weights.end(), 1.0f) - map[v].weights.begin());
    if (v % 3 == 0) map[v].weights = {0, 0, 0}, map[v].weights[(own + 1) % 3] = 0.5f;
    else map[v].weights = {0.25f, 0.25f, 0.25f};
    map[v].weights[own] = 0.5f;
  }
  const CornerAttributes uvs = transfer_uvs(target.mesh, target, map);
  for (int f = 0; f < target.mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = position(target.mesh, map[target.mesh.faces[f][k]]);
      const Uv got = uvs.uvs[uvs.face_uvs[f][k]];
      EXPECT_NEAR(got[0], p.x() / 5, kTolerance);
      EXPECT_NEAR(got[1], p.y() / 4, kTolerance);
    }
  EXPECT_TRUE(uvs.face_materials.empty());
}

// Two squares side by side, x in [0, 1] and [1, 2], in two islands of the texture: the left
// one at u = 0.1 + 0.3 x, the right one at u = 0.6 + 0.3 (x - 1); v = 0.5 y in both.
TexturedMesh two_islands() {
  TexturedMesh textured{grid(3, 2), {}};
  const TriangleMesh& mesh = textured.mesh;
  std::map<std::pair<int, bool>, int> numbers;
  for (const Face& face : mesh.faces) {
    const bool right = (mesh.vertices[face[0]].x() + mesh.vertices[face[1]].x() + mesh.vertices[face[2]].x()) / 3 > 1;
    std::array<int, 3> corners;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.vertices[face[k]];
      const auto [it, added] = numbers.try_emplace({face[k], right}, static_cast<int>(textured.corners.uvs.size()));
      if (added) textured.corners.uvs.push_back({right ? 0.6 + 0.3 * (p.x() - 1) : 0.1 + 0.3 * p.x(), 0.5 * p.y()});
      corners[k] = it->second;
    }
    textured.corners.face_uvs.push_back(corners);
  }
  return textured;
}

// The point of a flat mesh in the z = 0 plane at (x, y).
SurfacePoint locate(const TriangleMesh& mesh, double x, double y) {
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 &a = mesh.vertices[mesh.faces[f][0]], &b = mesh.vertices[mesh.faces[f][1]],
               &c = mesh.vertices[mesh.faces[f][2]];
    const auto cross = [](const Vec3& u, const Vec3& v) { return u.x() * v.y() - u.y() * v.x(); };
    const double area = cross(b - a, c - a);
    const Vec3 p(x, y, 0);
    const double wa = cross(b - p, c - p) / area, wb = cross(c - p, a - p) / area, wc = 1 - wa - wb;
    if (wa > 1e-9 && wb > 1e-9 && wc > 1e-9) return {f, {float(wa), float(wb), float(wc)}};
  }
  ADD_FAILURE() << "no face holds (" << x << ", " << y << ")";
  return {};
}

TEST(UvTransfer, ACornerOnAnotherIslandTakesTheNearestPointOfTheWinningOne) {
  const TexturedMesh target = two_islands();
  const std::vector<int> islands = uv_islands(target.mesh, target.corners);
  ASSERT_EQ(*std::max_element(islands.begin(), islands.end()), 1);
  // Two corners land on the left island, one on the right at (1.6, 0.4), whose nearest left
  // point is (1, 0.4). A fourth vertex is unmatched.
  TriangleMesh source;
  source.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
  source.faces = {{0, 1, 2}, {2, 1, 3}};
  const PreciseMap map = {locate(target.mesh, 0.3, 0.2), locate(target.mesh, 1.6, 0.4),
                          locate(target.mesh, 0.4, 0.7), SurfacePoint{}};
  const CornerAttributes uvs = transfer_uvs(source, target, map);
  const auto uv = [&](int f, int k) { return uvs.uvs[uvs.face_uvs[f][k]]; };
  const auto expect_uv = [&](int f, int k, double u, double v) {
    EXPECT_NEAR(uv(f, k)[0], u, kTolerance) << "face " << f << " corner " << k;
    EXPECT_NEAR(uv(f, k)[1], v, kTolerance) << "face " << f << " corner " << k;
  };
  expect_uv(0, 0, 0.1 + 0.3 * 0.3, 0.1);
  expect_uv(0, 1, 0.4, 0.2);  // moved onto the left island
  expect_uv(0, 2, 0.1 + 0.3 * 0.4, 0.35);
  // The second triangle: one corner on each island and one unmatched; the tie goes to the
  // first corner (left), and the unmatched one is (0, 0).
  expect_uv(1, 0, 0.1 + 0.3 * 0.4, 0.35);
  expect_uv(1, 1, 0.4, 0.2);
  EXPECT_EQ(uv(1, 2), (Uv{0, 0}));
}

TEST(UvTransfer, MapsThatDoNotFitAreInputErrors) {
  const TexturedMesh target = planar_grid();
  PreciseMap map(target.mesh.vertices.size());
  EXPECT_THROW(transfer_uvs(target.mesh, target, PreciseMap(3)), InputError);
  map[0].face = target.mesh.num_faces();
  EXPECT_THROW(transfer_uvs(target.mesh, target, map), InputError);
  TexturedMesh bare{target.mesh, {}};
  EXPECT_THROW(transfer_uvs(target.mesh, bare, PreciseMap(target.mesh.vertices.size())), InputError);
}

}  // namespace
}  // namespace isocorr
