// clean_mesh: each repair on a small hand-made mesh, the failures it must refuse, its speed
// on a 60K-vertex mesh, and the adjacency/geometry helpers it relies on.
#include "isocorr/mesh/mesh_cleaning.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/util/error.h"

#ifndef ISOCORR_SHARED_DATA_DIR
#define ISOCORR_SHARED_DATA_DIR "../shared/data"
#endif

namespace isocorr {
namespace {

TriangleMesh tetrahedron(const Vec3& offset = Vec3::Zero(), double scale = 1.0) {
  TriangleMesh mesh;
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)})
    mesh.vertices.push_back(offset + scale * p);
  mesh.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return mesh;
}

double signed_volume(const TriangleMesh& mesh) {
  double volume = 0.0;
  for (const Face& f : mesh.faces)
    volume += mesh.vertices[f[0]].dot(mesh.vertices[f[1]].cross(mesh.vertices[f[2]])) / 6.0;
  return volume;
}

bool mentions(const std::vector<std::string>& repairs, const std::string& words) {
  return std::any_of(repairs.begin(), repairs.end(),
                     [&](const std::string& r) { return r.find(words) != std::string::npos; });
}

std::string clean_error(const TriangleMesh& input, const CleaningOptions& options = {}) {
  try {
    clean_mesh(input, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string joined(const std::vector<std::string>& repairs) {
  std::string all;
  for (const std::string& r : repairs) all += r + "\n";
  return all;
}

// Closed torus of rings x segments vertices; inside out when `inward`.
TriangleMesh torus(int rings, int segments, bool inward = false) {
  TriangleMesh mesh;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double u = 2 * std::numbers::pi * i / rings, v = 2 * std::numbers::pi * j / segments;
      mesh.vertices.emplace_back((3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v));
    }
  auto id = [&](int i, int j) { return (i % rings) * segments + (j % segments); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      Face a = {id(i, j), id(i + 1, j), id(i + 1, j + 1)}, b = {id(i, j), id(i + 1, j + 1), id(i, j + 1)};
      if (inward) std::swap(a[1], a[2]), std::swap(b[1], b[2]);
      mesh.faces.push_back(a), mesh.faces.push_back(b);
    }
  return mesh;
}

TEST(MeshCleaning, CleanClosedMeshNeedsNoRepair) {
  const TriangleMesh input = tetrahedron();
  const CleanMesh clean = clean_mesh(input);
  EXPECT_TRUE(clean.repairs.empty()) << joined(clean.repairs);
  EXPECT_EQ(clean.mesh.faces, input.faces);
  EXPECT_EQ(clean.input_to_clean, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(clean.clean_to_input, (std::vector<int>{0, 1, 2, 3}));
}

TEST(MeshCleaning, WeldsDuplicateVertex) {
  TriangleMesh input = tetrahedron();
  input.vertices.push_back(input.vertices[0]);  // vertex 4 is a copy of vertex 0
  input.faces[2] = {4, 3, 2};
  const CleanMesh clean = clean_mesh(input);
  EXPECT_TRUE(mentions(clean.repairs, "welded 1 duplicate vertex")) << joined(clean.repairs);
  EXPECT_EQ(clean.mesh.num_vertices(), 4);
  EXPECT_EQ(clean.input_to_clean[4], clean.input_to_clean[0]);
  EXPECT_EQ(clean.clean_to_input[clean.input_to_clean[4]], 0);
  EXPECT_GT(signed_volume(clean.mesh), 0);
}

// Closed surfaces that merely touch (as in several FAUST remeshes) must not be welded into
// a non-manifold edge: here a thin closed tetrahedron whose edge 4-5 lies on edge 0-1.
TEST(MeshCleaning, KeepsCoincidentVerticesOfClosedSurfacesApart) {
  TriangleMesh input = tetrahedron();
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -0.2, 0), Vec3(0.5, -0.1, -0.2)})
    input.vertices.push_back(p);
  for (const Face& f : tetrahedron().faces) input.faces.push_back({f[0] + 4, f[1] + 4, f[2] + 4});
  const CleanMesh clean = clean_mesh(input);
  EXPECT_FALSE(mentions(clean.repairs, "welded")) << joined(clean.repairs);
  EXPECT_TRUE(mentions(clean.repairs, "kept the largest of 2")) << joined(clean.repairs);
  EXPECT_EQ(clean.input_to_clean[4], clean.input_to_clean[0]);
  EXPECT_EQ(clean.input_to_clean[5], clean.input_to_clean[1]);
}

TEST(MeshCleaning, DropsDegenerateAndDuplicateFaces) {
  TriangleMesh input = tetrahedron();
  input.vertices.emplace_back(0.5, 0, 0);  // midpoint of edge 0-1
  input.faces.push_back({0, 4, 1});        // zero area
  input.faces.push_back({2, 2, 3});        // repeated corner
  input.faces.push_back({3, 1, 0});        // same vertex set as face 1
  const CleanMesh clean = clean_mesh(input);
  EXPECT_TRUE(mentions(clean.repairs, "dropped 2 degenerate faces")) << joined(clean.repairs);
  EXPECT_TRUE(mentions(clean.repairs, "dropped 1 duplicate face")) << joined(clean.repairs);
  EXPECT_TRUE(mentions(clean.repairs, "dropped 1 vertex used by no face")) << joined(clean.repairs);
  EXPECT_EQ(clean.mesh.faces, tetrahedron().faces);
  EXPECT_EQ(clean.mesh.num_vertices(), 4);
  EXPECT_TRUE(clean.input_to_clean[4] == 0 || clean.input_to_clean[4] == 1);
}

// Every clean face names an input face with the same corners, corner by corner, through
// welds, dropped faces and re-oriented ones.
TEST(MeshCleaning, EveryFaceKnowsItsInputFace) {
  TriangleMesh input = tetrahedron();
  input.vertices.push_back(input.vertices[2]);  // a duplicate of vertex 2, used by face 3
  for (int& v : input.faces[3]) v = v == 2 ? 4 : v;
  std::swap(input.faces[1][1], input.faces[1][2]);  // one face turned against its neighbours
  input.faces.push_back({2, 2, 3});                 // degenerate, dropped
  const CleanMesh clean = clean_mesh(input);
  ASSERT_EQ(clean.clean_face_origins.size(), clean.mesh.faces.size());
  std::vector<bool> used(input.faces.size(), false);
  for (size_t f = 0; f < clean.mesh.faces.size(); ++f) {
    const CleanMesh::InputFace& origin = clean.clean_face_origins[f];
    ASSERT_GE(origin.face, 0);
    EXPECT_FALSE(used[origin.face]);
    used[origin.face] = true;
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(clean.mesh.faces[f][origin.clean_corner[k]], clean.input_to_clean[input.faces[origin.face][k]])
          << "face " << f << " corner " << k;
  }
  EXPECT_FALSE(used[4]);
}

TEST(MeshCleaning, KeepsLargestComponentAndMapsTheRest) {
  TriangleMesh input = tetrahedron(Vec3(10, 0, 0), 0.5);  // small one first, far away
  const TriangleMesh big = tetrahedron(Vec3::Zero(), 2.0);
  for (const Vec3& p : big.vertices) input.vertices.push_back(p);
  for (const Face& f : big.faces) input.faces.push_back({f[0] + 4, f[1] + 4, f[2] + 4});
  const CleanMesh clean = clean_mesh(input);
  EXPECT_TRUE(mentions(clean.repairs, "kept the largest of 2 connected components")) << joined(clean.repairs);
  EXPECT_TRUE(mentions(clean.repairs, "4 vertices outside it")) << joined(clean.repairs);
  ASSERT_EQ(clean.mesh.num_vertices(), 4);
  EXPECT_EQ(clean.clean_to_input, (std::vector<int>{4, 5, 6, 7}));
  // Every vertex of the small tetrahedron is nearest to the big one's vertex (2, 0, 0).
  for (int v = 0; v < 4; ++v) EXPECT_EQ(clean.input_to_clean[v], 1) << "vertex " << v;
  for (int v = 4; v < 8; ++v) EXPECT_EQ(clean.input_to_clean[v], v - 4);

  CleaningOptions strict;
  strict.keep_largest_component = false;
  EXPECT_NE(clean_error(input, strict).find("2 connected components"), std::string::npos);
}

TEST(MeshCleaning, ReorientsAFlippedFace) {
  TriangleMesh input = tetrahedron();
  std::swap(input.faces[2][1], input.faces[2][2]);
  const CleanMesh clean = clean_mesh(input);
  EXPECT_EQ(clean.repairs, (std::vector<std::string>{"re-oriented 1 face to agree with their neighbours"}));
  EXPECT_EQ(clean.mesh.faces, tetrahedron().faces);
  EXPECT_GT(signed_volume(clean.mesh), 0);
}

TEST(MeshCleaning, FlipsInsideOutMeshOutward) {
  TriangleMesh input = tetrahedron();
  for (Face& f : input.faces) std::swap(f[1], f[2]);
  ASSERT_LT(signed_volume(input), 0);
  const CleanMesh clean = clean_mesh(input);
  EXPECT_EQ(clean.repairs, (std::vector<std::string>{"flipped all faces to point outward"}));
  EXPECT_GT(signed_volume(clean.mesh), 0);
}

// Three faces on edge 0-1: a flat sheet (apexes 2 and 3 on opposite sides) and a fin (4).
TriangleMesh three_faces_on_an_edge() {
  TriangleMesh input;
  input.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  input.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  return input;
}

int faces_on_edge(const TriangleMesh& mesh, int a, int b) {
  return static_cast<int>(std::count_if(mesh.faces.begin(), mesh.faces.end(), [&](const Face& f) {
    return std::find(f.begin(), f.end(), a) != f.end() && std::find(f.begin(), f.end(), b) != f.end();
  }));
}

TEST(MeshCleaning, RejectsNonManifoldEdgeWhenRepairIsOff) {
  const TriangleMesh input = three_faces_on_an_edge();
  CleaningOptions strict;
  strict.repair_non_manifold_edges = false;
  EXPECT_THROW(clean_mesh(input, strict), InputError);
  EXPECT_NE(clean_error(input, strict).find("non-manifold edge between vertices 0 and 1"), std::string::npos)
      << clean_error(input, strict);
}

TEST(MeshCleaning, RepairsNonManifoldEdgeByKeepingTheFlattestPair) {
  const TriangleMesh input = three_faces_on_an_edge();
  const CleanMesh clean = clean_mesh(input);
  EXPECT_TRUE(mentions(clean.repairs, "dropped 1 face on 1 non-manifold edge (more than two faces per edge)"))
      << joined(clean.repairs);
  EXPECT_TRUE(mentions(clean.repairs, "dropped 1 vertex used by no face")) << joined(clean.repairs);
  ASSERT_EQ(clean.mesh.num_faces(), 2);
  ASSERT_EQ(clean.input_to_clean.size(), input.vertices.size());
  for (int v = 0; v < input.num_vertices(); ++v) {
    EXPECT_GE(clean.input_to_clean[v], 0) << "vertex " << v;
    EXPECT_LT(clean.input_to_clean[v], clean.mesh.num_vertices()) << "vertex " << v;
  }
  EXPECT_EQ(faces_on_edge(clean.mesh, clean.input_to_clean[0], clean.input_to_clean[1]), 2);
  // The fin is dropped, the sheet kept; its apex maps to the nearest kept vertex, 0.
  EXPECT_EQ(clean.clean_to_input, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(clean.input_to_clean[4], clean.input_to_clean[0]);
}

// Two flat sheets crossing along one edge (four faces on it): one sheet is kept whole,
// the other loses both faces there, and each edge ends with at most two faces.
TEST(MeshCleaning, RepairsCrossingSheetsByKeepingOne) {
  TriangleMesh input;
  input.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1.2}, {0, 0, -1.2}};
  input.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {1, 0, 5}};
  const CleanMesh clean = clean_mesh(input);
  EXPECT_TRUE(mentions(clean.repairs, "dropped 2 faces on 1 non-manifold edge")) << joined(clean.repairs);
  ASSERT_EQ(clean.mesh.num_faces(), 2);
  EXPECT_EQ(faces_on_edge(clean.mesh, clean.input_to_clean[0], clean.input_to_clean[1]), 2);
  const Vec3 n0 = (clean.mesh.vertices[clean.mesh.faces[0][1]] - clean.mesh.vertices[clean.mesh.faces[0][0]])
                      .cross(clean.mesh.vertices[clean.mesh.faces[0][2]] - clean.mesh.vertices[clean.mesh.faces[0][0]]);
  const Vec3 n1 = (clean.mesh.vertices[clean.mesh.faces[1][1]] - clean.mesh.vertices[clean.mesh.faces[1][0]])
                      .cross(clean.mesh.vertices[clean.mesh.faces[1][2]] - clean.mesh.vertices[clean.mesh.faces[1][0]]);
  EXPECT_GT(n0.normalized().dot(n1.normalized()), 0.999);  // one flat, consistently oriented sheet
}

// Two tetrahedra touching at one vertex: a non-manifold vertex, which needs no repair.
TEST(MeshCleaning, KeepsNonManifoldVertexAsItIs) {
  TriangleMesh input = tetrahedron();
  input.vertices.emplace_back(-1, 0, 0);
  input.vertices.emplace_back(0, -1, 0);
  input.vertices.emplace_back(0, 0, -1);
  for (const Face& f : tetrahedron().faces) {  // the mirror image through vertex 0
    const auto mirrored = [](int v) { return v == 0 ? 0 : v + 3; };
    input.faces.push_back({mirrored(f[0]), mirrored(f[2]), mirrored(f[1])});
  }
  ASSERT_GT(signed_volume(input), 0);
  const CleanMesh clean = clean_mesh(input);
  EXPECT_TRUE(clean.repairs.empty()) << joined(clean.repairs);
  EXPECT_EQ(clean.mesh.faces, input.faces);
}

TEST(MeshCleaning, RejectsMoebiusStrip) {
  const int segments = 8;
  TriangleMesh input;
  for (int i = 0; i < segments; ++i) {
    const double angle = 2 * std::numbers::pi * i / segments, twist = angle / 2;
    const Vec3 centre(3 * std::cos(angle), 3 * std::sin(angle), 0);
    const Vec3 across = std::cos(twist) * Vec3(std::cos(angle), std::sin(angle), 0) + std::sin(twist) * Vec3(0, 0, 1);
    input.vertices.push_back(centre + across);  // top i = 2i
    input.vertices.push_back(centre - across);  // bottom i = 2i + 1
  }
  for (int i = 0; i < segments; ++i) {
    const bool last = i == segments - 1;  // the half twist swaps top and bottom
    const int top = 2 * i, bottom = 2 * i + 1;
    const int next_top = last ? 1 : 2 * i + 2, next_bottom = last ? 0 : 2 * i + 3;
    input.faces.push_back({top, bottom, next_bottom});
    input.faces.push_back({top, next_bottom, next_top});
  }
  EXPECT_THROW(clean_mesh(input), InputError);
  EXPECT_NE(clean_error(input).find("non-orientable"), std::string::npos) << clean_error(input);
}

TEST(MeshCleaning, RejectsBadIndicesAndEmptyMeshes) {
  TriangleMesh input = tetrahedron();
  input.faces[1][2] = 7;
  EXPECT_THROW(clean_mesh(input), InputError);
  input.faces.clear();
  EXPECT_THROW(clean_mesh(input), InputError);
  input.faces = {{0, 0, 1}};
  EXPECT_THROW(clean_mesh(input), InputError);
}

TEST(MeshCleaning, CleansSixtyThousandVerticesQuickly) {
  TriangleMesh input = torus(250, 240, /*inward=*/true);
  ASSERT_EQ(input.num_vertices(), 60000);
  std::swap(input.faces[1234][1], input.faces[1234][2]);
  input.vertices.push_back(input.vertices[17]);  // an unused duplicate
  const auto start = std::chrono::steady_clock::now();
  const CleanMesh clean = clean_mesh(input);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 1.0);
  EXPECT_EQ(clean.mesh.num_vertices(), 60000);
  EXPECT_EQ(clean.input_to_clean[60000], clean.input_to_clean[17]);
  EXPECT_TRUE(mentions(clean.repairs, "re-oriented 1 face")) << joined(clean.repairs);
  EXPECT_TRUE(mentions(clean.repairs, "flipped all faces to point outward")) << joined(clean.repairs);
  EXPECT_GT(signed_volume(clean.mesh), 0);
}

// Coincident unused vertices once made welding quadratic (each one's radius search listed all
// the others): a million of them now clean as fast as any other million vertices.
TEST(MeshCleaning, MillionCoincidentUnusedVerticesWeldInOneGroup) {
  TriangleMesh input = tetrahedron();
  input.vertices.resize(4 + 1'000'000, Vec3(0.25, 0.25, 0.25));
  const CleanMesh clean = clean_mesh(input);
  EXPECT_EQ(clean.mesh.num_vertices(), 4);
  EXPECT_TRUE(mentions(clean.repairs, "welded 999999 duplicate vertices")) << joined(clean.repairs);
  EXPECT_EQ(clean.input_to_clean[4], clean.input_to_clean[1'000'003]);
}

// Cleaning works on normalised coordinates, so the scale of the file changes nothing: at
// 1e-160 every face's area once underflowed to zero and the mesh was refused.
TEST(MeshCleaning, ScaleOfTheCoordinatesChangesNothing) {
  const CleanMesh reference = clean_mesh(tetrahedron());
  for (const double scale : {1e-160, 1e160, 1e308}) {
    const CleanMesh clean = clean_mesh(tetrahedron(Vec3::Zero(), scale));
    EXPECT_EQ(clean.mesh.faces, reference.mesh.faces) << scale;
    for (int v = 0; v < 4; ++v)
      EXPECT_EQ(clean.normalisation.to_input(clean.mesh.vertices[v]), tetrahedron(Vec3::Zero(), scale).vertices[v]);
  }
  TriangleMesh collapsed = tetrahedron(Vec3(5, 5, 5), 0.0);
  EXPECT_THROW(clean_mesh(collapsed), InputError);
}

TEST(MeshCleaning, CleansRealMeshFromSharedData) {
  const std::string path = std::string(ISOCORR_SHARED_DATA_DIR) + "/tosca_hires/off/wolf0.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found at " << path;
  const LoadedMesh loaded = load_mesh(path);
  const CleanMesh clean = clean_mesh(loaded.mesh);
  EXPECT_EQ(clean.input_to_clean.size(), 4344u);
  EXPECT_EQ(clean.clean_to_input.size(), static_cast<size_t>(clean.mesh.num_vertices()));
  EXPECT_GT(signed_volume(clean.mesh), 0);
}

// TOPKIDS kid00, the reference shape of every TOPKIDS pair, has edge 8425-10765 in four
// faces: a triangle and its reversed copy hanging off a surface that continues across it.
TEST(MeshCleaning, RepairsNonManifoldEdgeOfTopkidsReference) {
  const std::string path = std::string(ISOCORR_SHARED_DATA_DIR) + "/topkids/off/kid00.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "TOPKIDS data not found at " << path;
  const LoadedMesh loaded = load_mesh(path);
  CleanMesh clean;
  ASSERT_NO_THROW(clean = clean_mesh(loaded.mesh));
  EXPECT_TRUE(mentions(clean.repairs, "non-manifold edge")) << joined(clean.repairs);
  EXPECT_TRUE(mentions(clean.repairs, "dropped 1 duplicate face")) << joined(clean.repairs);
  // The fin's third corner, 8426, is used by no other face.
  EXPECT_TRUE(mentions(clean.repairs, "dropped 1 vertex used by no face")) << joined(clean.repairs);
  EXPECT_EQ(std::count(clean.clean_to_input.begin(), clean.clean_to_input.end(), 8426), 0);
  ASSERT_EQ(clean.input_to_clean.size(), loaded.mesh.vertices.size());
  for (int v : clean.input_to_clean) ASSERT_TRUE(v >= 0 && v < clean.mesh.num_vertices());
  EXPECT_EQ(faces_on_edge(clean.mesh, clean.input_to_clean[8425], clean.input_to_clean[10765]), 2);
  CleaningOptions strict;
  strict.repair_non_manifold_edges = false;
  EXPECT_NE(clean_error(loaded.mesh, strict).find("non-manifold edge between vertices 8425 and 10765"),
            std::string::npos);
}

TEST(TriangleMesh, TopologyListsEachNeighbourOnceAndSorted) {
  const TriangleMesh mesh = tetrahedron();
  const MeshTopology topology(mesh);
  for (int v = 0; v < 4; ++v) {
    std::vector<int> neighbours(topology.neighbours_begin(v), topology.neighbours_end(v));
    std::vector<int> expected;
    for (int u = 0; u < 4; ++u)
      if (u != v) expected.push_back(u);
    EXPECT_EQ(neighbours, expected) << "vertex " << v;
    EXPECT_EQ(topology.faces_end(v) - topology.faces_begin(v), 3);
    for (const int* f = topology.faces_begin(v); f != topology.faces_end(v); ++f)
      EXPECT_NE(std::find(mesh.faces[*f].begin(), mesh.faces[*f].end(), v), mesh.faces[*f].end());
  }
}

TEST(TriangleMesh, AreasLengthsAndNormals) {
  const TriangleMesh mesh = tetrahedron();
  const double slanted = std::sqrt(3.0) / 2;
  EXPECT_NEAR(total_area(mesh), 1.5 + slanted, 1e-12);
  EXPECT_NEAR(mean_edge_length(mesh), (3 + 3 * std::sqrt(2.0)) / 6, 1e-12);
  const std::vector<double> areas = vertex_areas(mesh);
  EXPECT_NEAR(areas[0], 0.5, 1e-12);
  EXPECT_NEAR(areas[1], (1.0 + slanted) / 3, 1e-12);
  const std::vector<Vec3> normals = vertex_normals(mesh);
  EXPECT_NEAR(normals[0].norm(), 1.0, 1e-12);
  EXPECT_TRUE(normals[0].isApprox(-Vec3(1, 1, 1).normalized()));
  EXPECT_GT(normals[3].dot(Vec3(0, 0, 1)), 0);
}

}  // namespace
}  // namespace isocorr
