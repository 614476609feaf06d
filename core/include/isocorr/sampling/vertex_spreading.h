// Evenly spread vertices and the cells around them, by plain geometry: cheap helpers for
// stages that need a few thousand representative vertices (refinement's samples, the
// reduced eigenproblem's cells), where the salient geodesic sampling would cost too much.
#pragma once

#include <vector>

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

// About `count` evenly spread vertices (farthest-point order in Euclidean space, from
// vertex 0): all vertices when the mesh has fewer.
std::vector<int> spread_vertices(const TriangleMesh& mesh, int count);

// For every vertex, the index (into `centres`) of the nearest centre by edge hops:
// breadth-first from all at once, ties to the earlier centre. Vertices no centre reaches
// get 0.
std::vector<int> nearest_centre(const MeshTopology& topology, int vertex_count, const std::vector<int>& centres);

}  // namespace isocorr
