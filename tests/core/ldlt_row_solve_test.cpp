// The one-sweep solve for several right-hand sides gives Eigen's own solve (bit for bit
// under gcc; clang contracts other multiply-adds into FMAs, so to rounding there).
#include "isocorr/util/ldlt_row_solve.h"

#include <random>

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/spectral/laplace_beltrami.h"

namespace isocorr {
namespace {

template <int Columns>
void expect_same_as_eigen(unsigned seed) {
  // A Laplacian plus mass: sparse, symmetric positive definite, with fill-in when factored.
  const TriangleMesh mesh = limbed_blob(2);
  const Eigen::SparseMatrix<double> matrix =
      cotangent_laplacian(mesh) + Eigen::SparseMatrix<double>(lumped_mass(mesh).asDiagonal());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> factor(matrix);
  ASSERT_EQ(factor.info(), Eigen::Success);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  Eigen::Matrix<double, Eigen::Dynamic, Columns, Eigen::RowMajor> rows(matrix.rows(), Columns);
  for (Eigen::Index i = 0; i < rows.rows(); ++i)
    for (int j = 0; j < Columns; ++j) rows(i, j) = uniform(random);
  const Eigen::MatrixXd right_sides = rows;
  const Eigen::MatrixXd expected = factor.solve(right_sides);
  solve_rows_in_place(factor, rows);
  EXPECT_LE((Eigen::MatrixXd(rows) - expected).cwiseAbs().maxCoeff(), 1e-13 * expected.cwiseAbs().maxCoeff());
  EXPECT_LT((matrix * Eigen::MatrixXd(rows) - right_sides).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(LdltRowSolve, ThreeSidesAsEigenSolvesThem) { expect_same_as_eigen<3>(1); }

TEST(LdltRowSolve, EightSidesAsEigenSolvesThem) { expect_same_as_eigen<8>(2); }

}  // namespace
}  // namespace isocorr
