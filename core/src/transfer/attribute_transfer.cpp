#include "isocorr/transfer/attribute_transfer.h"

#include <limits>
#include <string>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

void check_rows(size_t rows, size_t target_vertices, const char* what) {
  if (rows != target_vertices)
    throw InputError(std::string("the ") + what + " have " + std::to_string(rows) + " rows for a target of " +
                     std::to_string(target_vertices) + " vertices");
}

void check_table(const VertexTable& table) {
  if (table.columns < 1 || table.values.size() != static_cast<size_t>(table.rows) * table.columns)
    throw InputError("the attribute table's values do not fill its rows and columns");
}

void check_face(const TriangleMesh& target, const SurfacePoint& point, size_t v) {
  if (point.face >= target.num_faces())
    throw InputError("the precise map puts source vertex " + std::to_string(v) + " on face " +
                     std::to_string(point.face) + ", outside the target's " + std::to_string(target.num_faces()) +
                     " faces");
}

void check_image(int image, size_t rows, size_t v) {
  if (image < -1 || image >= static_cast<int64_t>(rows))
    throw InputError("the map sends source vertex " + std::to_string(v) + " to " + std::to_string(image) +
                     ", outside the target's " + std::to_string(rows) + " vertices");
}

}  // namespace

VertexTable pull_values(const VertexTable& target_values, const std::vector<int>& map) {
  check_table(target_values);
  VertexTable out{static_cast<int>(map.size()), target_values.columns, {}};
  out.values.assign(map.size() * out.columns, std::numeric_limits<double>::quiet_NaN());
  for (size_t v = 0; v < map.size(); ++v) {
    check_image(map[v], target_values.rows, v);
    if (map[v] < 0) continue;
    for (int c = 0; c < out.columns; ++c)
      out.values[v * out.columns + c] = target_values.values[static_cast<size_t>(map[v]) * out.columns + c];
  }
  return out;
}

VertexTable pull_values(const TriangleMesh& target, const VertexTable& target_values, const PreciseMap& map) {
  check_table(target_values);
  check_rows(target_values.rows, target.vertices.size(), "attributes");
  VertexTable out{static_cast<int>(map.size()), target_values.columns, {}};
  out.values.assign(map.size() * out.columns, std::numeric_limits<double>::quiet_NaN());
  for (size_t v = 0; v < map.size(); ++v) {
    check_face(target, map[v], v);
    if (map[v].face < 0) continue;
    const Face& face = target.faces[map[v].face];
    for (int c = 0; c < out.columns; ++c) {
      double value = 0;
      for (int j = 0; j < 3; ++j) value += map[v].weights[j] * target_values.values[static_cast<size_t>(face[j]) * out.columns + c];
      out.values[v * out.columns + c] = value;
    }
  }
  return out;
}

std::vector<int64_t> pull_labels(const std::vector<int64_t>& target_labels, const std::vector<int>& map) {
  std::vector<int64_t> out(map.size(), kUnmatchedLabel);
  for (size_t v = 0; v < map.size(); ++v) {
    check_image(map[v], target_labels.size(), v);
    if (map[v] >= 0) out[v] = target_labels[map[v]];
  }
  return out;
}

std::vector<int64_t> pull_labels(const TriangleMesh& target, const std::vector<int64_t>& target_labels,
                                 const PreciseMap& map) {
  check_rows(target_labels.size(), target.vertices.size(), "labels");
  std::vector<int64_t> out(map.size(), kUnmatchedLabel);
  for (size_t v = 0; v < map.size(); ++v) {
    check_face(target, map[v], v);
    if (map[v].face < 0) continue;
    const Face& face = target.faces[map[v].face];
    // The weight each distinct label of the three corners holds.
    int64_t best = 0;
    double best_weight = -1;
    for (int j = 0; j < 3; ++j) {
      const int64_t label = target_labels[face[j]];
      double weight = 0;
      for (int k = 0; k < 3; ++k)
        if (target_labels[face[k]] == label) weight += map[v].weights[k];
      if (weight > best_weight || (weight == best_weight && label < best)) best = label, best_weight = weight;
    }
    out[v] = best;
  }
  return out;
}

}  // namespace isocorr
