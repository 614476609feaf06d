// The descent's result does not depend on whether it remembers the vertices it costed:
// a bumpy cost with many local minima, from every start, reaches the same vertex and
// cost both ways, and remembering costs fewer vertices.
#include "isocorr/matching/surface_descent.h"

#include <gtest/gtest.h>

#include <cmath>

#include "isocorr/mesh/procedural_meshes.h"

namespace isocorr {
namespace {

// A smooth trend towards one pole plus a ripple: local minima all over the sphere.
float bumpy(const Vec3& p) {
  return static_cast<float>(p.z() + 0.3 * std::sin(9 * p.x()) * std::cos(7 * p.y()));
}

TEST(SurfaceDescent, RememberingCostedVerticesChangesTheWorkNotTheResult) {
  const TriangleMesh sphere = icosphere(4);
  const MeshTopology topology(sphere);
  long cheap_calls = 0, dear_calls = 0;
  int differing = 0;
  for (int start = 0; start < static_cast<int>(sphere.vertices.size()); start += 7) {
    float cheap_best = 0, dear_best = 0;
    const int cheap = descend_to_minimum<CostPrice::kCheap>(
        topology, start, [&](int w) { return ++cheap_calls, bumpy(sphere.vertices[w]); }, cheap_best);
    const int dear = descend_to_minimum<CostPrice::kDear>(
        topology, start, [&](int w) { return ++dear_calls, bumpy(sphere.vertices[w]); }, dear_best);
    differing += cheap != dear || cheap_best != dear_best;
  }
  EXPECT_EQ(differing, 0);
  EXPECT_LT(dear_calls, cheap_calls * 2 / 3);
}

TEST(SurfaceDescent, ALongDescentPastTheTableStillReachesTheMinimum) {
  // From the north pole to the south pole of a fine sphere: hundreds of costed vertices,
  // more than the table remembers.
  const TriangleMesh sphere = icosphere(5);
  const MeshTopology topology(sphere);
  int north = 0, south = 0;
  for (int v = 0; v < static_cast<int>(sphere.vertices.size()); ++v) {
    if (sphere.vertices[v].z() > sphere.vertices[north].z()) north = v;
    if (sphere.vertices[v].z() < sphere.vertices[south].z()) south = v;
  }
  float best = 0;
  const int reached = descend_to_minimum<CostPrice::kDear>(
      topology, north, [&](int w) { return static_cast<float>(sphere.vertices[w].z()); }, best);
  EXPECT_EQ(reached, south);
  EXPECT_FLOAT_EQ(best, static_cast<float>(sphere.vertices[south].z()));
}

}  // namespace
}  // namespace isocorr
