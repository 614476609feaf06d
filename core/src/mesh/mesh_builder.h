// The mesh every reader fills: vertices and fan-triangulated polygons, validated as they
// arrive so that a message can name the record at fault.
#pragma once

#include <algorithm>
#include <climits>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "isocorr/mesh/mesh_io.h"
#include "text_scanning.h"

namespace isocorr::mesh_formats {

// Where in the file something is, formatted only when a message needs it.
struct Place {
  const char* what;  // "vertex", "face", "the face on line", ...
  long long number;
};
inline std::ostream& operator<<(std::ostream& out, const Place& place) {
  return out << place.what << ' ' << place.number;
}

// Collects vertices and fan-triangulated polygons, validating each as it arrives.
class MeshBuilder {
 public:
  // `index_base` is how the file writes its first vertex (OBJ: 1), for messages.
  MeshBuilder(const char* format, int index_base) : format_(format), index_base_(index_base) {}

  // Once the vertex count is known, indices are checked on arrival; otherwise in finish().
  void expect(long long vertices, long long polygons) {
    declared_vertices_ = vertices;
    mesh_.vertices.reserve(static_cast<size_t>(vertices));
    mesh_.faces.reserve(static_cast<size_t>(polygons));
  }
  // Room for the triangles a text of `bytes` can hold (each corner past a polygon's second
  // takes at least two bytes), so that the face list is never copied to grow. Only the
  // memory the triangles fill is touched, so an unused reservation costs nothing.
  void reserve_for_text(size_t bytes) { mesh_.faces.reserve(bytes / 2 + 1); }
  long long vertex_count() const { return static_cast<long long>(mesh_.vertices.size()); }
  // Triangles kept so far: a reader that records per-face data watches it grow.
  size_t face_count() const { return mesh_.faces.size(); }

  void add_vertex(double x, double y, double z, Place place) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      fail(format_, cat(place, " has a non-finite coordinate (", x, ", ", y, ", ", z, ")"));
    mesh_.vertices.emplace_back(x, y, z);
  }

  void require_corner_count(long long corners, Place place) const {
    if (corners < 3) fail(format_, cat(place, " has ", corners, " corners; a face needs at least 3"));
  }

  // A polygon arrives corner by corner (0-based indices) and is fan-triangulated as it
  // arrives: no list of its corners is kept, so a polygon of millions of corners costs only
  // its triangles. A fan triangle that repeats a corner has no area and is not kept.
  void begin_polygon(Place place) {
    polygon_place_ = place;
    polygon_corners_ = 0;
  }
  void add_corner(long long index) {
    const Place& place = polygon_place_;
    if (index < 0) fail(format_, cat(place, " refers to the negative vertex index ", index + index_base_));
    if (declared_vertices_ >= 0 && index >= declared_vertices_) out_of_range(place, index, declared_vertices_);
    if (index > INT_MAX) fail(format_, cat(place, " refers to vertex ", index + index_base_, ", which is out of range"));
    if (index > max_index_) max_index_ = index, max_index_place_ = place;
    const int corner = static_cast<int>(index);
    if (polygon_corners_ == 0) first_corner_ = corner;
    if (polygon_corners_ >= 2) {
      if (corner == first_corner_ || corner == previous_corner_ || previous_corner_ == first_corner_) ++repeated_corner_triangles_;
      else add_triangle({first_corner_, previous_corner_, corner});
    }
    previous_corner_ = corner;
    ++polygon_corners_;
  }
  void end_polygon() {
    require_corner_count(polygon_corners_, polygon_place_);
    if (polygon_corners_ > 3) ++split_polygons_;
  }

  LoadedMesh finish(std::string format_name) {
    if (mesh_.faces.empty()) fail(format_, "the file has no faces");
    if (max_index_ >= vertex_count()) out_of_range(max_index_place_, max_index_, vertex_count());
    LoadedMesh loaded{std::move(mesh_), std::move(format_name), {}};
    if (split_polygons_ > 0)
      loaded.notes.push_back(cat("split ", split_polygons_, split_polygons_ == 1 ? " polygon" : " polygons",
                                 " with more than three corners into triangles (fan triangulation)"));
    if (repeated_corner_triangles_ > 0)
      loaded.notes.push_back(cat("dropped ", repeated_corner_triangles_,
                                 repeated_corner_triangles_ == 1 ? " triangle" : " triangles",
                                 " that repeat a corner of their polygon"));
    return loaded;
  }

 private:
  // A closed surface has about two triangles per vertex (Euler's formula); a file with far more
  // is no surface the engine can match, and refusing it as it is read bounds the memory a
  // small file can make the reader take (a polygon of millions of corners over a few vertices).
  static constexpr long long kMaxTrianglesPerVertex = 16;
  static constexpr long long kAnyFileMayHave = 1024;  // triangles, whatever its vertex count

  void add_triangle(const Face& triangle) {
    const long long vertices = std::max(declared_vertices_, vertex_count());
    if (static_cast<long long>(mesh_.faces.size()) >= kMaxTrianglesPerVertex * vertices + kAnyFileMayHave)
      fail(format_, cat(polygon_place_, " makes the file's triangles more than ", kMaxTrianglesPerVertex,
                        " per vertex (", vertices, " vertices); a surface has about two"));
    mesh_.faces.push_back(triangle);
  }

  [[noreturn]] void out_of_range(Place place, long long index, long long vertices) const {
    fail(format_, cat(place, " refers to vertex ", index + index_base_, " but the file has ", vertices, " vertices"));
  }

  const char* format_;
  int index_base_;
  long long declared_vertices_ = -1;
  long long max_index_ = -1;
  Place max_index_place_{"face", 0};
  long long split_polygons_ = 0;
  long long repeated_corner_triangles_ = 0;
  Place polygon_place_{"face", 0};
  long long polygon_corners_ = 0;
  int first_corner_ = 0, previous_corner_ = 0;
  TriangleMesh mesh_;
};

}  // namespace isocorr::mesh_formats
