// Smoothed mean and Gaussian curvature: known values on a sphere and a plane, Gauss-Bonnet,
// invariance to rigid motion, scale and numbering, and the disagreement along right and
// wrong maps.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/shape/mean_curvature.h"
#include "isocorr/spectral/laplace_beltrami.h"

namespace isocorr {
namespace {

// A sphere of radius r has H = 1 / r everywhere and area 4 pi r^2: the dimensionless value
// is sqrt(4 pi) at every vertex and every scale. The cotangent formula is off by a few per
// cent at the icosphere's 12 five-valent vertices; smoothing spreads that out.
TEST(MeanCurvature, IsUniformOnASphere) {
  const TriangleMesh sphere = icosphere(4);
  const Eigen::MatrixXf h = smoothed_mean_curvature(sphere, vertex_normals(sphere));
  ASSERT_EQ(h.rows(), sphere.num_vertices());
  ASSERT_EQ(h.cols(), static_cast<int>(kCurvatureScales.size()));
  const double expected = std::sqrt(4 * M_PI);
  std::vector<double> deviation;
  for (int j = 0; j < h.cols(); ++j) {
    EXPECT_NEAR(h.col(j).mean(), expected, 0.005 * expected);
    deviation.push_back((h.col(j).array() - expected).abs().maxCoeff());
  }
  EXPECT_LT(deviation.front(), 0.08 * expected);
  EXPECT_LT(deviation.back(), 0.02 * expected);
  EXPECT_LT(deviation.back(), deviation.front() / 3);
}

// Flipping the normals flips the sign: the value says convex or concave, not only how
// curved.
TEST(MeanCurvature, SignFollowsTheNormals) {
  const TriangleMesh sphere = icosphere(3);
  std::vector<Vec3> inward = vertex_normals(sphere);
  for (Vec3& n : inward) n = -n;
  const Eigen::MatrixXf outward = smoothed_mean_curvature(sphere, vertex_normals(sphere));
  EXPECT_LT((smoothed_mean_curvature(sphere, inward) + outward).array().abs().maxCoeff(), 1e-4);
}

TEST(MeanCurvature, IsTheSameOnARotatedScaledRenumberedCopy) {
  const TriangleMesh blob = limbed_blob(3);
  const RenumberedCopy copy = rotated_scaled_renumbered(blob, 2.5, 3);
  const Eigen::MatrixXf original = smoothed_mean_curvature(blob, vertex_normals(blob));
  const Eigen::MatrixXf copied = smoothed_mean_curvature(copy.mesh, vertex_normals(copy.mesh));
  double largest_difference = 0;
  for (int v = 0; v < blob.num_vertices(); ++v)
    largest_difference = std::max<double>(
        largest_difference, (original.row(v) - copied.row(copy.permutation[v])).cwiseAbs().maxCoeff());
  EXPECT_LT(largest_difference, 1e-3 * original.cwiseAbs().maxCoeff());
  // The blob's limbs make it far from a sphere: the values vary.
  EXPECT_GT(original.col(0).maxCoeff() - original.col(0).minCoeff(), 1.0);
}

// K = 1 / r^2 and area 4 pi r^2: K area = 4 pi at every vertex and every scale. The angle
// defect is exact in total (Gauss-Bonnet) but uneven between the icosphere's five- and
// six-valent vertices; smoothing evens it out.
TEST(GaussianCurvature, IsFourPiOnASphere) {
  const TriangleMesh sphere = icosphere(4);
  const SmoothedCurvature curvature = smoothed_mean_and_gaussian_curvature(sphere, vertex_normals(sphere));
  ASSERT_EQ(curvature.gaussian.rows(), sphere.num_vertices());
  ASSERT_EQ(curvature.gaussian.cols(), static_cast<int>(kCurvatureScales.size()));
  const double expected = 4 * M_PI;
  for (int j = 0; j < curvature.gaussian.cols(); ++j)
    EXPECT_NEAR(curvature.gaussian.col(j).mean(), expected, 0.005 * expected);
  EXPECT_LT((curvature.gaussian.col(2).array() - expected).abs().maxCoeff(), 0.05 * expected);
  // The mean curvature is the same as smoothed_mean_curvature's.
  EXPECT_EQ((curvature.mean - smoothed_mean_curvature(sphere, vertex_normals(sphere))).cwiseAbs().maxCoeff(), 0.f);
}

// Gauss-Bonnet: the total curvature of a closed genus-0 surface is 4 pi whatever its shape,
// and the smoothing keeps totals (its heat step conserves the mass-weighted sum).
TEST(GaussianCurvature, TotalsFourPiOnAClosedGenusZeroSurface) {
  const TriangleMesh blob = limbed_blob(3);
  const SmoothedCurvature curvature = smoothed_mean_and_gaussian_curvature(blob, vertex_normals(blob));
  const Eigen::VectorXd mass = lumped_mass(blob);
  for (int j = 0; j < curvature.gaussian.cols(); ++j) {
    const double mean = mass.dot(curvature.gaussian.col(j).cast<double>()) / mass.sum();
    EXPECT_NEAR(mean, 4 * M_PI, 1e-4 * 4 * M_PI);
  }
  // Limbs: positive at their tips, negative where they join the body.
  EXPECT_GT(curvature.gaussian.col(0).maxCoeff(), 4 * M_PI);
  EXPECT_LT(curvature.gaussian.col(0).minCoeff(), 0.f);
}

// A flat sheet has none inside, and its straight edges none either (pi less the two corner
// angles of a straight boundary vertex is 0): only the four corners carry curvature, and the
// centre, far from them at every scale, stays at zero.
TEST(GaussianCurvature, IsZeroInsideAFlatSheet) {
  const TriangleMesh sheet = grid(20, 20);
  const SmoothedCurvature curvature = smoothed_mean_and_gaussian_curvature(sheet, vertex_normals(sheet));
  int centre = 0;
  Vec3 middle = Vec3::Zero();
  for (const Vec3& p : sheet.vertices) middle += p / sheet.num_vertices();
  for (int v = 0; v < sheet.num_vertices(); ++v)
    if ((sheet.vertices[v] - middle).norm() < (sheet.vertices[centre] - middle).norm()) centre = v;
  for (int j = 0; j < curvature.gaussian.cols(); ++j) EXPECT_NEAR(curvature.gaussian(centre, j), 0.f, 1e-4);
  EXPECT_GT(curvature.gaussian.col(0).maxCoeff(), 1.f);  // at the corners
}

TEST(GaussianCurvature, IsTheSameOnARotatedScaledRenumberedCopy) {
  const TriangleMesh blob = limbed_blob(3);
  const RenumberedCopy copy = rotated_scaled_renumbered(blob, 0.4, 11);
  const Eigen::MatrixXf original =
      smoothed_mean_and_gaussian_curvature(blob, vertex_normals(blob)).gaussian;
  const Eigen::MatrixXf copied =
      smoothed_mean_and_gaussian_curvature(copy.mesh, vertex_normals(copy.mesh)).gaussian;
  double largest_difference = 0;
  for (int v = 0; v < blob.num_vertices(); ++v)
    largest_difference = std::max<double>(
        largest_difference, (original.row(v) - copied.row(copy.permutation[v])).cwiseAbs().maxCoeff());
  EXPECT_LT(largest_difference, 1e-3 * original.cwiseAbs().maxCoeff());
}

TEST(MeanCurvature, DisagreementIsZeroAlongTheTrueMapOnly) {
  const TriangleMesh blob = limbed_blob(3);
  const RenumberedCopy copy = rotated_scaled_renumbered(blob, 0.6, 8);
  const Eigen::MatrixXf source = smoothed_mean_curvature(blob, vertex_normals(blob));
  const Eigen::MatrixXf target = smoothed_mean_curvature(copy.mesh, vertex_normals(copy.mesh));
  const int n = blob.num_vertices();
  std::vector<std::pair<int, int>> truth, shifted;
  for (int v = 0; v < n; ++v) {
    truth.emplace_back(v, copy.permutation[v]);
    shifted.emplace_back(v, copy.permutation[(static_cast<long long>(v) * 7919 + 13) % n]);
  }
  const double along_truth = curvature_disagreement(source, target, truth);
  EXPECT_LT(along_truth, 1e-3);
  EXPECT_GT(curvature_disagreement(source, target, shifted), 100 * along_truth + 0.05);
  EXPECT_EQ(curvature_disagreement(source, target, {}), 0.0);
}

}  // namespace
}  // namespace isocorr
