// Per-vertex attributes carried across a map: colours, skin weights, scalar fields (values,
// interpolated) and segment labels (integers, never interpolated). A map sends source
// vertices to the target, so attributes are pulled from the target onto the source.
#pragma once

#include <cstdint>
#include <vector>

#include "isocorr/mesh/triangle_mesh.h"
#include "isocorr/transfer/precise_map.h"

namespace isocorr {

// `columns` values per vertex, row by row.
struct VertexTable {
  int rows = 0, columns = 1;
  std::vector<double> values;
};

// Unmatched source vertices (map -1, face -1) get NaN values and this label.
inline constexpr int64_t kUnmatchedLabel = -1;

// The target rows of each source vertex's image. Throws InputError when the table does
// not have one row per target vertex or the map is not one entry per source vertex.
VertexTable pull_values(const VertexTable& target_values, const std::vector<int>& map);
// The target rows interpolated at each source vertex's point.
VertexTable pull_values(const TriangleMesh& target, const VertexTable& target_values, const PreciseMap& map);

// Labels (one column): through a vertex map, the image's; through a precise map, the label
// holding the most weight among the point's face corners (ties: the lower label).
std::vector<int64_t> pull_labels(const std::vector<int64_t>& target_labels, const std::vector<int>& map);
std::vector<int64_t> pull_labels(const TriangleMesh& target, const std::vector<int64_t>& target_labels,
                                 const PreciseMap& map);

}  // namespace isocorr
