// Carrying a texture across a correspondence: every source triangle corner takes the UV
// of the target point its vertex lands on (a precise map), and the triangle takes the
// material of the target face it lands in.
#pragma once

#include <vector>

#include "isocorr/mesh/textured_mesh.h"
#include "isocorr/transfer/precise_map.h"

namespace isocorr {

// The UV islands of a mesh: faces joined across every edge whose two faces give both its
// ends the same UV (the same vt index, or vt entries of equal coordinates, since some
// exporters write one vt per corner). Island numbers per face, from 0 in order of first face.
// Throws InputError if the attributes do not fit the mesh.
std::vector<int> uv_islands(const TriangleMesh& mesh, const CornerAttributes& corners);

// Corner attributes for `source` from the UVs and materials of `target`, where map[v] is the
// point of target.mesh that source vertex v lands on (map.size() == #V of source).
//
// A corner's UV is its point's barycentric mix of the target face's corner UVs (a corner
// without a vt counts as (0, 0)). An unmatched vertex (face -1) gets UV (0, 0).
// Seams: a triangle takes all three UVs from one chart, the part of a target UV island
// around the triangle's landed corners (so a cut inside one island counts as a seam too).
// Candidates are grown from each corner's face and from the face its centre lands on; the
// chart holding the most of the three landed points wins (ties: the one nearest the centre,
// then the first corner's), and a corner landing off it takes the UV of the chart's nearest
// point in 3D (closest point on the nearest face). A triangle's material is that of the
// winning chart's face nearest its centre.
//
// Result: `uvs` shared by the corners of one vertex that get the same UV, `face_uvs` for
// every face; the target's material library and materials (-1 where no corner is
// matched; the list empty if the target has none); no normals (the
// source's own, if any, still fit its faces). Throws InputError when the map does not fit
// the meshes or the target has no texture coordinates.
CornerAttributes transfer_uvs(const TriangleMesh& source, const TexturedMesh& target, const PreciseMap& map);

}  // namespace isocorr
