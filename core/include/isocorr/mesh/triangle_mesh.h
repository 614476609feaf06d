// The triangle mesh every part of the engine works on, and its vertex/face adjacency.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace isocorr {

using Vec3 = Eigen::Vector3d;
using Face = std::array<int, 3>;

// Plain indexed triangle mesh. `vertices` #V, `faces` #F with 0-based vertex indices.
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<Face> faces;

  int num_vertices() const { return static_cast<int>(vertices.size()); }
  int num_faces() const { return static_cast<int>(faces.size()); }
};

// Compressed adjacency lists built once per mesh: the one-ring of every vertex and the
// faces around it. Geodesics and the dense search walk these in their inner loops.
class MeshTopology {
 public:
  explicit MeshTopology(const TriangleMesh& mesh);

  // Neighbouring vertices of v (each listed once).
  const int* neighbours_begin(int v) const { return neighbours_.data() + neighbour_offsets_[v]; }
  const int* neighbours_end(int v) const { return neighbours_.data() + neighbour_offsets_[v + 1]; }
  // Faces incident to v.
  const int* faces_begin(int v) const { return vertex_faces_.data() + face_offsets_[v]; }
  const int* faces_end(int v) const { return vertex_faces_.data() + face_offsets_[v + 1]; }

 private:
  std::vector<int> neighbour_offsets_, neighbours_;
  std::vector<int> face_offsets_, vertex_faces_;
};

// Derived per-mesh quantities used for normalisation and orientation tests.
double total_area(const TriangleMesh& mesh);
double mean_edge_length(const TriangleMesh& mesh);
// Area-weighted vertex normals (unit length; zero for isolated vertices).
std::vector<Vec3> vertex_normals(const TriangleMesh& mesh);
// One third of the area of the faces around each vertex (barycentric lumped area).
std::vector<double> vertex_areas(const TriangleMesh& mesh);

// The vertices on the boundary (ends of an edge that only one face has), ascending; empty
// when the surface is closed.
std::vector<int> boundary_vertices(const TriangleMesh& mesh);

}  // namespace isocorr
