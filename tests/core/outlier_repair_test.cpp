// Outlier repair: a misplaced region placed again, the rest left alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/refinement/outlier_repair.h"
#include "spectral_test_shapes.h"

namespace isocorr {
namespace {

using test_support::spectral_options;

// A region sent to the far side of the body (the 3% of vertices nearest one limb's tip,
// each mapped where its point reflected through the centre lies) is placed again from the
// geodesic distances to the rest of the map; nothing else moves.
TEST(OutlierRepair, PlacesAMisplacedRegionAgainAndLeavesTheRestAlone) {
  const TriangleMesh blob = limbed_blob(4);
  const RenumberedCopy copy = rotated_scaled_renumbered(blob, 1.7, 5);
  const auto source = PreprocessedShape::build(blob, spectral_options());
  const auto target = PreprocessedShape::build(copy.mesh, spectral_options());
  const int n = blob.num_vertices();
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : blob.vertices) centre += p / n;
  int tip = 0;
  for (int v = 0; v < n; ++v)
    if ((blob.vertices[v] - centre).norm() > (blob.vertices[tip] - centre).norm()) tip = v;
  const std::vector<float> from_tip = source->geodesics().distance_field(tip);
  std::vector<int> by_distance(n);
  for (int v = 0; v < n; ++v) by_distance[v] = v;
  std::sort(by_distance.begin(), by_distance.end(), [&](int a, int b) { return from_tip[a] < from_tip[b]; });
  const std::vector<int> region(by_distance.begin(), by_distance.begin() + n * 3 / 100);
  auto nearest_vertex = [&](const Vec3& point) {
    int best = 0;
    for (int w = 0; w < n; ++w)
      if ((blob.vertices[w] - point).squaredNorm() < (blob.vertices[best] - point).squaredNorm()) best = w;
    return best;
  };
  std::vector<int> forward = copy.permutation;
  for (const int v : region) forward[v] = copy.permutation[nearest_vertex(2 * centre - blob.vertices[v])];

  const OutlierRepair repair = repair_outliers(*source, *target, forward, 2);
  EXPECT_GE(repair.moved, static_cast<int>(region.size() * 9 / 10));
  int placed = 0;
  std::vector<bool> in_region(n, false);
  for (const int v : region) in_region[v] = true;
  const MeshTopology& topology = target->geodesics().topology();
  for (const int v : region) {
    bool near = forward[v] == copy.permutation[v];
    for (const int* w = topology.neighbours_begin(copy.permutation[v]); w != topology.neighbours_end(copy.permutation[v]); ++w)
      near = near || forward[v] == *w;
    placed += near;
  }
  EXPECT_GE(placed, static_cast<int>(region.size() * 9 / 10));
  for (int v = 0; v < n; ++v)
    if (!in_region[v]) ASSERT_EQ(forward[v], copy.permutation[v]) << "vertex " << v << " outside the region moved";
}

}  // namespace
}  // namespace isocorr
