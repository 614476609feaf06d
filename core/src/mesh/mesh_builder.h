// The mesh every reader fills: vertices and fan-triangulated polygons, validated as they
// arrive so that a message can name the record at fault.
#pragma once

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
  long long vertex_count() const { return static_cast<long long>(mesh_.vertices.size()); }

  void add_vertex(double x, double y, double z, Place place) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      fail(format_, cat(place, " has a non-finite coordinate (", x, ", ", y, ", ", z, ")"));
    mesh_.vertices.emplace_back(x, y, z);
  }

  void require_corner_count(long long corners, Place place) const {
    if (corners < 3) fail(format_, cat(place, " has ", corners, " corners; a face needs at least 3"));
  }

  // `corners` are 0-based.
  void add_polygon(const std::vector<long long>& corners, Place place) {
    require_corner_count(static_cast<long long>(corners.size()), place);
    for (long long index : corners) {
      if (index < 0) fail(format_, cat(place, " refers to the negative vertex index ", index + index_base_));
      if (declared_vertices_ >= 0 && index >= declared_vertices_) out_of_range(place, index, declared_vertices_);
      if (index > INT_MAX)
        fail(format_, cat(place, " refers to vertex ", index + index_base_, ", which is out of range"));
      if (index > max_index_) max_index_ = index, max_index_place_ = place;
    }
    for (size_t k = 1; k + 1 < corners.size(); ++k)
      mesh_.faces.push_back({static_cast<int>(corners[0]), static_cast<int>(corners[k]),
                             static_cast<int>(corners[k + 1])});
    if (corners.size() > 3) ++split_polygons_;
  }

  LoadedMesh finish(std::string format_name) {
    if (mesh_.faces.empty()) fail(format_, "the file has no faces");
    if (max_index_ >= vertex_count()) out_of_range(max_index_place_, max_index_, vertex_count());
    LoadedMesh loaded{std::move(mesh_), std::move(format_name), {}};
    if (split_polygons_ > 0)
      loaded.notes.push_back(cat("split ", split_polygons_, split_polygons_ == 1 ? " polygon" : " polygons",
                                 " with more than three corners into triangles (fan triangulation)"));
    return loaded;
  }

 private:
  [[noreturn]] void out_of_range(Place place, long long index, long long vertices) const {
    fail(format_, cat(place, " refers to vertex ", index + index_base_, " but the file has ", vertices, " vertices"));
  }

  const char* format_;
  int index_base_;
  long long declared_vertices_ = -1;
  long long max_index_ = -1;
  Place max_index_place_{"face", 0};
  long long split_polygons_ = 0;
  TriangleMesh mesh_;
};

}  // namespace isocorr::mesh_formats
