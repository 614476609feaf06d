// Ground-truth scores and coverage on a flat grid, where geodesics are straight lines.
#include "isocorr/eval/metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

constexpr int kSide = 30;          // vertices per row and column
constexpr double kSpacing = 0.1;

int vid(int row, int col) { return row * kSide + col; }

TriangleMesh flat_grid() {
  TriangleMesh mesh;
  for (int r = 0; r < kSide; ++r)
    for (int c = 0; c < kSide; ++c) mesh.vertices.emplace_back(c * kSpacing, r * kSpacing, 0.0);
  for (int r = 0; r + 1 < kSide; ++r)
    for (int c = 0; c + 1 < kSide; ++c) {
      mesh.faces.push_back({vid(r, c), vid(r, c + 1), vid(r + 1, c + 1)});
      mesh.faces.push_back({vid(r, c), vid(r + 1, c + 1), vid(r + 1, c)});
    }
  return mesh;
}

class GridMetrics : public ::testing::Test {
 protected:
  GridMetrics() : mesh_(flat_grid()), topology_(mesh_), geodesics_(mesh_, topology_) {}

  // Maps every vertex through `column` (row kept).
  template <typename F>
  std::vector<int> map_columns(F&& column) const {
    std::vector<int> map(kSide * kSide);
    for (int r = 0; r < kSide; ++r)
      for (int c = 0; c < kSide; ++c) map[vid(r, c)] = vid(r, column(c));
    return map;
  }
  // Identity ground truth over all vertices, optionally with the left/right mirror.
  GroundTruth identity_truth(bool with_mirror) const {
    GroundTruth gt;
    const std::vector<int> mirror = map_columns([](int c) { return kSide - 1 - c; });
    for (int v = 0; v < kSide * kSide; ++v) {
      gt.source.push_back(v);
      gt.target.push_back(v);
      if (with_mirror) gt.mirrored_target.push_back(mirror[v]);
    }
    return gt;
  }
  GroundTruthScore score(const std::vector<int>& forward, const GroundTruth& gt, int max_points = 0) const {
    EvaluationOptions options;
    options.max_points = max_points;
    options.threads = 2;
    return score_against_ground_truth(mesh_, geodesics_, diameter_, forward, gt, options);
  }

  TriangleMesh mesh_;
  MeshTopology topology_;
  FastMarching geodesics_;
  const double diameter_ = std::sqrt(2.0) * (kSide - 1) * kSpacing;  // the square's diagonal
};

TEST_F(GridMetrics, IdentityIsPerfect) {
  const std::vector<int> identity = map_columns([](int c) { return c; });
  for (bool mirror : {false, true}) {
    const GroundTruthScore s = score(identity, identity_truth(mirror));
    EXPECT_EQ(s.evaluated, kSide * kSide);
    EXPECT_DOUBLE_EQ(s.mean_error, 0.0);
    EXPECT_DOUBLE_EQ(s.max_error, 0.0);
    EXPECT_DOUBLE_EQ(s.kim_auc, 1.0);
    ASSERT_EQ(s.kim_thresholds.size(), 101u);
    EXPECT_DOUBLE_EQ(s.kim_thresholds.back(), 0.25);
    EXPECT_DOUBLE_EQ(s.far_fraction, 0.0);
    EXPECT_EQ(s.mirrored_fraction, mirror ? 0.0 : -1.0);
    EXPECT_TRUE(s.flip_free);
    EXPECT_FALSE(s.flip_rule.empty());
  }
}

TEST_F(GridMetrics, ShiftByOneColumn) {
  const std::vector<int> shifted = map_columns([](int c) { return std::min(c + 1, kSide - 1); });
  GroundTruth gt;  // every column but the last, whose image is clamped
  for (int r = 0; r < kSide; ++r)
    for (int c = 0; c + 1 < kSide; ++c) {
      gt.source.push_back(vid(r, c));
      gt.target.push_back(vid(r, c));
    }
  const GroundTruthScore s = score(shifted, gt);
  const double expected = kSpacing / diameter_;
  EXPECT_NEAR(s.mean_error, expected, 0.05 * expected);
  EXPECT_NEAR(s.max_error, expected, 0.05 * expected);
  const double kim = kSpacing / std::sqrt(total_area(mesh_));
  EXPECT_NEAR(s.mean_kim_error, kim, 0.05 * kim);
  EXPECT_LT(s.kim_auc, 1.0);
  EXPECT_TRUE(s.flip_free);
}

TEST_F(GridMetrics, StridedSubsetIsDeterministic) {
  const std::vector<int> shifted = map_columns([](int c) { return std::min(c + 2, kSide - 1); });
  const GroundTruthScore a = score(shifted, identity_truth(false), 97);
  const GroundTruthScore b = score(shifted, identity_truth(false), 97);
  EXPECT_EQ(a.evaluated, 97);
  EXPECT_EQ(a.mean_error, b.mean_error);
  EXPECT_EQ(a.kim_curve, b.kim_curve);
}

TEST_F(GridMetrics, MirrorMapIsAFlip) {
  const std::vector<int> mirror = map_columns([](int c) { return kSide - 1 - c; });
  const GroundTruthScore s = score(mirror, identity_truth(true));
  EXPECT_GT(s.mirrored_fraction, 0.3);
  EXPECT_FALSE(s.flip_free);
  // Scored against the mirror itself, the map is perfect.
  GroundTruth flipped = identity_truth(true);
  std::swap(flipped.target, flipped.mirrored_target);
  EXPECT_TRUE(score(mirror, flipped).flip_free);
}

TEST_F(GridMetrics, BadIndicesAreInputErrors) {
  std::vector<int> map = map_columns([](int c) { return c; });
  map[5] = kSide * kSide;
  EXPECT_THROW(score(map, identity_truth(false)), InputError);
  EXPECT_THROW(coverage(mesh_, geodesics_, map, {10}), InputError);
}

TEST_F(GridMetrics, Coverage) {
  const std::vector<int> identity = map_columns([](int c) { return c; });
  for (double c : coverage(mesh_, geodesics_, identity, {50, 10, 200})) EXPECT_NEAR(c, 1.0, 1e-9);
  const std::vector<int> constant(kSide * kSide, vid(15, 15));
  const std::vector<double> few = coverage(mesh_, geodesics_, constant, {10, 50});
  ASSERT_EQ(few.size(), 2u);
  EXPECT_GT(few[0], 0.0);
  EXPECT_LT(few[0], 0.3);
  EXPECT_LT(few[1], 0.1);
  // Half the grid mapped onto itself, the other half collapsed: about half covered.
  std::vector<int> half = identity;
  for (int v = 0; v < kSide * kSide; ++v)
    if (v % kSide >= kSide / 2) half[v] = vid(0, 0);
  EXPECT_NEAR(coverage(mesh_, geodesics_, half, {100})[0], 0.5, 0.1);
}

// A part's map is measured against where its true image lies, not against the whole target.
TEST_F(GridMetrics, CoverageOfTrueImage) {
  // The left third of the grid is the part; its true images are itself.
  std::vector<int> part_images;
  for (int r = 0; r < kSide; ++r)
    for (int c = 0; c < kSide / 3; ++c) part_images.push_back(vid(r, c));
  // Right: every cell its true image reaches (whole-target coverage says about a third).
  EXPECT_NEAR(coverage_of_true_image(mesh_, geodesics_, part_images, part_images, 100), 1.0, 1e-9);
  EXPECT_LT(coverage(mesh_, geodesics_, part_images, {100})[0], 0.5);
  // Shifted onto the right third: none of the owed cells.
  std::vector<int> shifted;
  for (int v : part_images) shifted.push_back(v + 2 * kSide / 3);
  EXPECT_LT(coverage_of_true_image(mesh_, geodesics_, shifted, part_images, 100), 0.05);
  // Collapsed onto the first row: only the cells along it.
  std::vector<int> squeezed;
  for (int v : part_images) squeezed.push_back(v % kSide);
  const double squeezed_coverage = coverage_of_true_image(mesh_, geodesics_, squeezed, part_images, 100);
  EXPECT_GT(squeezed_coverage, 0.0);
  EXPECT_LT(squeezed_coverage, 0.4);
  EXPECT_THROW(coverage_of_true_image(mesh_, geodesics_, part_images, {kSide * kSide}, 100), InputError);
}

}  // namespace
}  // namespace isocorr
