// Precise maps: each vertex sent to a point of the other surface (a triangle and
// barycentric weights) instead of to the nearest vertex. Between meshes of different
// resolutions a vertex map is as coarse as the target's edges; a precise map is not.
//
// The point of a source vertex v is found from the vertex map around it: the source
// vertices near v (rings grown until their images are at least kMinDistinctImages target
// vertices) and their images are aligned by the similarity transform of least squares
// (rotation, uniform scale, shift; Umeyama 1991), so v's place among its neighbours is
// carried onto the target the way the map carries the neighbourhood, and that position is
// projected onto the nearest target triangle around v's image (the triangles of its image's
// two-ring). One local step of an as-rigid-as-possible fit: the map's snapping noise, which
// the neighbours average, leaves the point, and the pose change does not enter it.
#pragma once

#include <array>
#include <vector>

#include "isocorr/mesh/mesh_cleaning.h"
#include "isocorr/mesh/triangle_mesh.h"
#include "isocorr/transfer/surface_point.h"

namespace isocorr {

inline constexpr int kMinDistinctImages = 6;

// The precise map of a vertex map: for every vertex of `source`, its point on `target`.
// `map` sends every source vertex to a target vertex (-1: unmatched, which stays
// unmatched). Both meshes in the numbering `map` uses (the files'). Throws InputError when
// the map does not fit the meshes. On `threads` workers (0 = all cores); the result does
// not depend on it.
PreciseMap precise_map(const TriangleMesh& source, const TriangleMesh& target, const std::vector<int>& map,
                       int threads = 1);

// The same for a vertex map between two cleaned meshes (`clean_map` in their numbering),
// given in the files' terms: a point for every input vertex of `source`, on an input face
// of `target` (a vertex merged away by cleaning takes the point of the vertex it became).
PreciseMap precise_map_in_files(const CleanMesh& source, const CleanMesh& target, const std::vector<int>& clean_map,
                                int threads = 1);

// The point of triangle (a, b, c) nearest p, as barycentric weights of a, b and c.
Eigen::Vector3d nearest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// The position of a surface point.
Vec3 surface_position(const TriangleMesh& mesh, const SurfacePoint& point);

// The vertex of the point's face with the largest weight (the vertex map a precise map
// rounds to).
int nearest_corner(const TriangleMesh& mesh, const SurfacePoint& point);

}  // namespace isocorr
