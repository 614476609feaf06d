// Meshes the project generates itself: for unit tests with known answers, the bundled
// demo, and size-scaling benchmarks (the benchmark data may not be redistributed).
#pragma once

#include <cstdint>
#include <vector>

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

// Unit sphere from a subdivided icosahedron: 10 * 4^level + 2 vertices.
TriangleMesh icosphere(int level);

// Flat grid in the z = 0 plane, `nx` x `ny` vertices, spacing 1, optionally jittered
// (fraction of the spacing) so the triangulation is irregular.
TriangleMesh grid(int nx, int ny, double jitter = 0, uint32_t seed = 1);

// An asymmetric "creature": an icosphere with limbs of different lengths and widths in
// irregular directions. No intrinsic symmetry, so the correct map is unique.
TriangleMesh limbed_blob(int level);

// A creature with one exact symmetry: turning it by 180 degrees about the z axis, (x, y, z)
// -> (-x, -y, z), maps it onto itself, vertex onto vertex (up to rounding). Two limbs of each of two lengths,
// one of each turned into the other, and a head on the axis. That turn keeps handedness, so
// the map and the map composed with the turn are equally right: only a landmark tells them
// apart. No other symmetry: the limbs point in irregular directions.
TriangleMesh twofold_blob(int level);

// A rotated, scaled and renumbered copy: vertex i of `mesh` becomes vertex
// `permutation[i]` of the copy, faces are shuffled. Isometric up to scale.
struct RenumberedCopy {
  TriangleMesh mesh;
  std::vector<int> permutation;
};
RenumberedCopy rotated_scaled_renumbered(const TriangleMesh& mesh, double scale, uint32_t seed);

}  // namespace isocorr
