// The cotangent Laplacian and its eigenbasis against analytic spectra (sphere, rectangle)
// and the algebraic properties ZoomOut relies on.
#include "isocorr/spectral/laplace_beltrami.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

// [0, a] x [0, b] triangulated as a regular (or jittered) grid of nx x ny vertices.
TriangleMesh rectangle(double a, double b, int nx, int ny, double jitter = 0) {
  TriangleMesh mesh = grid(nx, ny, jitter, 3);
  for (Vec3& p : mesh.vertices) p = Vec3(p.x() * a / (nx - 1), p.y() * b / (ny - 1), 0);
  return mesh;
}

// Neumann eigenvalues of [0, a] x [0, b]: pi^2 (m^2 / a^2 + n^2 / b^2), ascending.
std::vector<double> rectangle_spectrum(double a, double b, int count) {
  std::vector<double> values;
  for (int m = 0; m < 20; ++m)
    for (int n = 0; n < 20; ++n) values.push_back(M_PI * M_PI * (m * m / (a * a) + n * n / (b * b)));
  std::sort(values.begin(), values.end());
  values.resize(count);
  return values;
}

void expect_mass_orthonormal(const LaplaceBasis& basis) {
  const Eigen::MatrixXd gram =
      basis.eigenvectors.transpose() * basis.mass.asDiagonal() * basis.eigenvectors;
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(gram.rows(), gram.cols());
  EXPECT_LT((gram - identity).cwiseAbs().maxCoeff(), 1e-8);
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
  const LaplaceBasis basis = compute_laplace_basis(mesh, 10);
  EXPECT_TRUE(basis.eigenvectors.allFinite());
  expect_mass_orthonormal(basis);
}

// Unit sphere: eigenvalues l (l + 1) with multiplicity 2l + 1. Level 4 has 2562 vertices
// (edges about 0.08 long). The discretisation error grows like (l h)^2, and the inscribed
// polyhedron has 0.12% less area than the sphere; the worst measured relative error for
// l <= 3 is 0.36%. 2% leaves a 5x margin for other compilers and platforms while still
// catching a wrong weight (a lost factor 1/2 or a sign is off by 50% or more).
TEST(LaplaceBeltrami, SphereSpectrumIsLTimesLPlusOne) {
  const TriangleMesh sphere = icosphere(4);
  // k = (l_max + 1)^2 takes whole multiplets. Plain Lanczos missed a copy of l = 1 at k = 4
  // and of l = 3 at k = 16 (an l + 1 vector took its place).
  for (const int k : {4, 9, 16}) {
    const LaplaceBasis basis = compute_laplace_basis(sphere, k);
    ASSERT_EQ(basis.eigenvalues.size(), k);
    EXPECT_NEAR(basis.eigenvalues[0], 0, 1e-8);
    int index = 1;
    for (int l = 1; index < k; ++l) {
      const double exact = l * (l + 1);
      for (int m = 0; m < 2 * l + 1; ++m, ++index) {
        EXPECT_NEAR(basis.eigenvalues[index], exact, 0.02 * exact) << "k = " << k << ", l = " << l;
      }
    }
    for (int i = 1; i < k; ++i) EXPECT_GE(basis.eigenvalues[i], basis.eigenvalues[i - 1]);
    expect_mass_orthonormal(basis);
  }
}

// Neumann spectrum of a 1.3 x 1 rectangle (side ratio chosen so the first eigenvalues are
// distinct), spacing 0.02. The error is again O(h^2); the worst measured relative error of
// the first 12 is 0.30% on the regular grid and on the jittered one, so 1% is a 3x margin.
TEST(LaplaceBeltrami, RectangleNeumannSpectrum) {
  const double a = 1.3, b = 1;
  const int count = 12;
  const std::vector<double> exact = rectangle_spectrum(a, b, count);
  for (const double jitter : {0.0, 0.3}) {
    const LaplaceBasis basis = compute_laplace_basis(rectangle(a, b, 66, 51, jitter), count);
    ASSERT_EQ(basis.eigenvalues.size(), count);
    EXPECT_NEAR(basis.eigenvalues[0], 0, 1e-8);
    for (int i = 1; i < count; ++i) {
      EXPECT_NEAR(basis.eigenvalues[i], exact[i], 0.01 * exact[i]) << "jitter " << jitter << ", index " << i;
    }
    expect_mass_orthonormal(basis);
  }
}

TEST(LaplaceBeltrami, FirstEigenvectorIsConstant) {
  const TriangleMesh blob = limbed_blob(3);
  const LaplaceBasis basis = compute_laplace_basis(blob, 8);
  const double constant = 1 / std::sqrt(total_area(blob));  // M-unit, positive by the sign rule
  EXPECT_LT((basis.eigenvectors.col(0).array() - constant).abs().maxCoeff(), 1e-6 * constant);
  EXPECT_LT(std::abs(basis.eigenvalues[0]), 1e-8 * basis.eigenvalues[1]);
  expect_mass_orthonormal(basis);
}

TEST(LaplaceBeltrami, LargestEntryOfEveryEigenvectorIsPositive) {
  const LaplaceBasis basis = compute_laplace_basis(limbed_blob(3), 20);
  for (Eigen::Index c = 0; c < basis.eigenvectors.cols(); ++c) {
    EXPECT_GE(basis.eigenvectors.col(c).maxCoeff(), -basis.eigenvectors.col(c).minCoeff());
  }
}

TEST(LaplaceBeltrami, KIsCappedAtVerticesMinusOne) {
  const TriangleMesh tiny = icosphere(0);  // 12 vertices
  const LaplaceBasis basis = compute_laplace_basis(tiny, 50);
  EXPECT_EQ(basis.eigenvalues.size(), 11);
  EXPECT_EQ(basis.eigenvectors.cols(), 11);
  expect_mass_orthonormal(basis);
}

TEST(LaplaceBeltrami, BadInputIsAnInputError) {
  EXPECT_THROW(compute_laplace_basis(icosphere(1), 0), InputError);
  TriangleMesh with_stray_vertex = icosphere(1);
  with_stray_vertex.vertices.push_back(Vec3(3, 0, 0));
  EXPECT_THROW(compute_laplace_basis(with_stray_vertex, 5), InputError);
  LaplaceBasisOptions no_restarts;
  no_restarts.max_restarts = 0;
  no_restarts.tolerance = 1e-300;
  EXPECT_THROW(compute_laplace_basis(icosphere(3), 30, no_restarts), InputError);
}

// A cancelled job must not wait for the eigensolver (minutes on a large mesh): it stops at
// its next linear solve.
TEST(LaplaceBeltrami, CancelledJobStopsTheSolver) {
  const std::atomic<bool> cancel{true};
  JobControl control;
  control.cancel_requested = &cancel;
  LaplaceBasisOptions options;
  options.control = &control;
  EXPECT_THROW(compute_laplace_basis(icosphere(3), 20, options), Cancelled);
  options.control = nullptr;
  EXPECT_EQ(compute_laplace_basis(icosphere(3), 20, options).eigenvalues.size(), 20);
}

}  // namespace
}  // namespace isocorr
