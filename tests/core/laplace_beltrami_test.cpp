// The cotangent Laplacian and lumped mass: the algebraic properties the eigensolver relies on.
#include "isocorr/spectral/laplace_beltrami.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"

namespace isocorr {
namespace {

// [0, a] x [0, b] triangulated as a regular (or jittered) grid of nx x ny vertices.
TriangleMesh rectangle(double a, double b, int nx, int ny, double jitter = 0) {
  TriangleMesh mesh = grid(nx, ny, jitter, 3);
  for (Vec3& p : mesh.vertices) p = Vec3(p.x() * a / (nx - 1), p.y() * b / (ny - 1), 0);
  return mesh;
}

TEST(LaplaceBeltrami, MassSumsToTheArea) {
  for (const TriangleMesh& mesh : {icosphere(3), rectangle(1.3, 1, 20, 15, 0.3), limbed_blob(3)}) {
    const Eigen::VectorXd mass = lumped_mass(mesh);
    ASSERT_EQ(mass.size(), mesh.num_vertices());
    EXPECT_GT(mass.minCoeff(), 0);
    EXPECT_NEAR(mass.sum(), total_area(mesh), 1e-12 * total_area(mesh));
  }
}

TEST(LaplaceBeltrami, LaplacianIsSymmetricWithZeroRowSums) {
  // With and without boundary, regular and irregular.
  for (const TriangleMesh& mesh : {icosphere(3), rectangle(1.3, 1, 20, 15, 0.3), limbed_blob(3)}) {
    const Eigen::SparseMatrix<double> laplacian = cotangent_laplacian(mesh);
    ASSERT_EQ(laplacian.rows(), mesh.num_vertices());
    EXPECT_EQ((laplacian - Eigen::SparseMatrix<double>(laplacian.transpose())).norm(), 0);
    const Eigen::VectorXd diagonal = laplacian.diagonal();
    EXPECT_GT(diagonal.minCoeff(), 0);
    const Eigen::VectorXd row_sums = laplacian * Eigen::VectorXd::Ones(mesh.num_vertices());
    EXPECT_LT(row_sums.cwiseAbs().maxCoeff(), 1e-12 * diagonal.maxCoeff());
  }
}

TEST(LaplaceBeltrami, SliversStayBoundedAndPositiveSemiDefinite) {
  TriangleMesh mesh = rectangle(1, 1, 6, 6);
  // Vertex (x, y) is 6 y + x, spacing 0.2; face {a, b, d} spans (x, y), (x + 1, y), (x + 1, y + 1).
  mesh.vertices[8] = mesh.vertices[7];                                      // coincident corners
  mesh.vertices[21] = Vec3(0.5 * (mesh.vertices[20] + mesh.vertices[27]));  // a flat triangle
  mesh.vertices[28] += Vec3(0, 0.9999 * 0.2, 0);                            // slivers
  const Eigen::MatrixXd laplacian = Eigen::MatrixXd(cotangent_laplacian(mesh));
  ASSERT_TRUE(laplacian.allFinite());
  const Eigen::MatrixXd off_diagonal = laplacian - Eigen::MatrixXd(laplacian.diagonal().asDiagonal());
  EXPECT_LE(off_diagonal.cwiseAbs().maxCoeff(), kMaxCotangent);
  const Eigen::VectorXd spectrum = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(laplacian).eigenvalues();
  EXPECT_GT(spectrum.minCoeff(), -1e-9 * spectrum.maxCoeff());
}

}  // namespace
}  // namespace isocorr
