// Views: right-handed frames, the principal view moving with the mesh, the fit in a rectangle.
#include "isocorr/render/view.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

void expect_right_handed(const ViewFrame& f, const std::string& name) {
  EXPECT_NEAR(f.right.norm(), 1, 1e-9) << name;
  EXPECT_NEAR(f.up.norm(), 1, 1e-9) << name;
  EXPECT_NEAR(f.right.dot(f.up), 0, 1e-9) << name;
  EXPECT_LT((f.right.cross(f.up) + f.forward).norm(), 1e-9) << name;  // never a mirror image
}

TEST(View, EveryNamedViewIsARightHandedFrame) {
  const TriangleMesh mesh = limbed_blob(2);
  for (const std::string& name : view_names()) expect_right_handed(view_frame(name, mesh), name);
  const ViewFrame front = view_frame("+z", mesh);
  EXPECT_EQ(front.right, Vec3::UnitX());
  EXPECT_EQ(front.up, Vec3::UnitY());
  EXPECT_THROW(view_frame("sideways", mesh), InputError);
}

TEST(View, PrincipalViewTurnsWithTheMesh) {
  const TriangleMesh mesh = limbed_blob(3);
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.7, Vec3::UnitX()) * Eigen::AngleAxisd(-2.1, Vec3(1, 2, 3).normalized())).toRotationMatrix();
  TriangleMesh moved = mesh;
  for (Vec3& p : moved.vertices) p = 2.5 * (turn * p) + Vec3(4, -1, 7);
  const ViewFrame before = view_frame("principal", mesh), after = view_frame("principal", moved);
  expect_right_handed(after, "principal");
  EXPECT_LT((turn * before.right - after.right).norm(), 1e-6);
  EXPECT_LT((turn * before.up - after.up).norm(), 1e-6);
  EXPECT_LT((turn * before.forward - after.forward).norm(), 1e-6);
}

TEST(View, TheSourceIsSeenThroughTheMapAsTheTargetIs) {
  const TriangleMesh creature = limbed_blob(3);
  const RenumberedCopy moved = rotated_scaled_renumbered(creature, 1.7, 11);
  const ViewFrame target = view_frame("principal", moved.mesh);
  const ViewFrame source = view_frame_through_map(creature, moved.mesh, moved.permutation, target);
  expect_right_handed(source, "through the map");
  // The copy is the creature turned: seen the same way, each vertex lands at the same
  // (scaled) place, so the frames agree on every vertex pair's differences.
  const Vec3 a = creature.vertices[0] - creature.vertices[100];
  const Vec3 b = moved.mesh.vertices[moved.permutation[0]] - moved.mesh.vertices[moved.permutation[100]];
  EXPECT_NEAR(1.7 * a.dot(source.right), b.dot(target.right), 1e-6);
  EXPECT_NEAR(1.7 * a.dot(source.up), b.dot(target.up), 1e-6);
  EXPECT_NEAR(1.7 * a.dot(source.forward), b.dot(target.forward), 1e-6);
  // A map that says nothing about direction: the source's own principal view.
  const std::vector<int> collapsed(creature.vertices.size(), 0);
  const ViewFrame fallback = view_frame_through_map(creature, moved.mesh, collapsed, target);
  EXPECT_LT((fallback.up - view_frame("principal", creature).up).norm(), 1e-12);
}

TEST(View, FitCentresTheMeshInsideTheMarginKeepingItsProportions) {
  TriangleMesh mesh = grid(3, 2);  // 2 x 1 in the z = 0 plane
  const std::vector<ScreenPoint> points = fit_into(mesh, view_frame("+z", mesh), Rect{100, 0, 50, 40}, 5);
  ASSERT_EQ(points.size(), 6u);
  double low_x = 1e9, high_x = -1e9, low_y = 1e9, high_y = -1e9;
  for (const ScreenPoint& p : points)
    low_x = std::min(low_x, p.x), high_x = std::max(high_x, p.x), low_y = std::min(low_y, p.y), high_y = std::max(high_y, p.y);
  EXPECT_DOUBLE_EQ(low_x, 105);  // the width limits: 40 pixels for 2 units
  EXPECT_DOUBLE_EQ(high_x, 145);
  EXPECT_DOUBLE_EQ(high_y - low_y, 20);
  EXPECT_DOUBLE_EQ((low_y + high_y) / 2, 20);
  EXPECT_GT(points[0].y, points[3].y);  // y = 0 row lies below the y = 1 row: up is up
}

}  // namespace
}  // namespace isocorr
