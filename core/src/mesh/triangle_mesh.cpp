// Adjacency (CSR) and per-mesh geometric quantities of TriangleMesh.
#include "isocorr/mesh/triangle_mesh.h"

#include <algorithm>
#include <cstdint>
#include <utility>

#include <Eigen/Geometry>

namespace isocorr {

namespace {

// Turns per-vertex counts into CSR offsets (offsets[v]..offsets[v+1]).
std::vector<int> offsets_from_counts(const std::vector<int>& counts) {
  std::vector<int> offsets(counts.size() + 1, 0);
  for (size_t v = 0; v < counts.size(); ++v) offsets[v + 1] = offsets[v] + counts[v];
  return offsets;
}

Vec3 face_cross(const TriangleMesh& mesh, const Face& f) {
  const Vec3& a = mesh.vertices[f[0]];
  return (mesh.vertices[f[1]] - a).cross(mesh.vertices[f[2]] - a);
}

}  // namespace

MeshTopology::MeshTopology(const TriangleMesh& mesh) {
  const int nv = mesh.num_vertices();
  std::vector<int> face_counts(nv, 0);
  for (const Face& f : mesh.faces)
    for (int v : f) ++face_counts[v];

  face_offsets_ = offsets_from_counts(face_counts);
  vertex_faces_.resize(face_offsets_.back());
  std::vector<int> cursor(face_offsets_.begin(), face_offsets_.end() - 1);
  for (int fi = 0; fi < mesh.num_faces(); ++fi)
    for (int v : mesh.faces[fi]) vertex_faces_[cursor[v]++] = fi;

  // Each corner contributes its two face-neighbours; interior edges appear twice, so the
  // raw lists are sorted and deduplicated in place before compaction.
  std::vector<int> raw(2 * face_offsets_.back());
  for (int v = 0; v < nv; ++v) cursor[v] = 2 * face_offsets_[v];
  for (const Face& f : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      const int v = f[k];
      raw[cursor[v]++] = f[(k + 1) % 3];
      raw[cursor[v]++] = f[(k + 2) % 3];
    }
  neighbour_offsets_.assign(nv + 1, 0);
  neighbours_.clear();
  neighbours_.reserve(raw.size() / 2 + nv);
  for (int v = 0; v < nv; ++v) {
    auto begin = raw.begin() + 2 * face_offsets_[v];
    auto end = raw.begin() + 2 * face_offsets_[v + 1];
    std::sort(begin, end);
    neighbours_.insert(neighbours_.end(), begin, std::unique(begin, end));
    neighbour_offsets_[v + 1] = static_cast<int>(neighbours_.size());
  }
}

double total_area(const TriangleMesh& mesh) {
  double area = 0.0;
  for (const Face& f : mesh.faces) area += 0.5 * face_cross(mesh, f).norm();
  return area;
}

double mean_edge_length(const TriangleMesh& mesh) {
  // Unique undirected edges: each keyed by (min, max) packed into 64 bits.
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * mesh.faces.size());
  for (const Face& f : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      const auto [a, b] = std::minmax(f[k], f[(k + 1) % 3]);
      edges.push_back((static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b));
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  if (edges.empty()) return 0.0;
  double sum = 0.0;
  for (std::uint64_t e : edges)
    sum += (mesh.vertices[e >> 32] - mesh.vertices[e & 0xffffffffu]).norm();
  return sum / static_cast<double>(edges.size());
}

std::vector<Vec3> vertex_normals(const TriangleMesh& mesh) {
  // The unnormalised cross product is twice the area times the normal: area weighting.
  std::vector<Vec3> normals(mesh.vertices.size(), Vec3::Zero());
  for (const Face& f : mesh.faces) {
    const Vec3 n = face_cross(mesh, f);
    for (int v : f) normals[v] += n;
  }
  for (Vec3& n : normals) {
    const double len = n.norm();
    if (len > 0.0) n /= len;
  }
  return normals;
}

std::vector<double> vertex_areas(const TriangleMesh& mesh) {
  std::vector<double> areas(mesh.vertices.size(), 0.0);
  for (const Face& f : mesh.faces) {
    const double third = face_cross(mesh, f).norm() / 6.0;
    for (int v : f) areas[v] += third;
  }
  return areas;
}

std::vector<int> boundary_vertices(const TriangleMesh& mesh) {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(3 * mesh.faces.size());
  for (const Face& f : mesh.faces)
    for (int c = 0; c < 3; ++c) edges.emplace_back(std::minmax(f[c], f[(c + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  std::vector<int> boundary;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) boundary.push_back(edges[i].first), boundary.push_back(edges[i].second);
    i = j;
  }
  std::sort(boundary.begin(), boundary.end());
  boundary.erase(std::unique(boundary.begin(), boundary.end()), boundary.end());
  return boundary;
}

}  // namespace isocorr
