// Solves with a sparse LDL^T factor for a few right-hand sides at once.
//
// Eigen's own solve sweeps the factor once per right-hand side. Stored as rows (one row
// per unknown, the right sides side by side), a single sweep updates all of them with
// each factor entry, so the factor is read once: on 52K vertices, three sides (the
// rigidity polish's coordinates) took a third of the time, eight (a Lanczos block) a fifth.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCholesky>

namespace isocorr {

// rows <- A^-1 rows for the factor of A: the steps of Eigen's SimplicialLDLT::solve
// (permute, L, D, L^T, permute back; L's unit diagonal is not stored), in its order of
// operations: built by gcc, the result is the same to the last bit (clang contracts other
// multiply-adds into FMAs, which moves the last bits).
template <int Columns>
void solve_rows_in_place(const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower>& factor,
                         Eigen::Matrix<double, Eigen::Dynamic, Columns, Eigen::RowMajor>& rows) {
  using Row = Eigen::Matrix<double, Columns, 1>;
  using Lower = Eigen::SparseMatrix<double>;
  const Lower& lower = factor.matrixL().nestedExpression();
  const Eigen::VectorXd& diagonal = factor.vectorD();
  const Eigen::Index n = rows.rows();
  rows = factor.permutationP() * rows;
  auto row = [&](Eigen::Index i) { return Eigen::Map<Row>(rows.row(i).data()); };
  for (Eigen::Index j = 0; j < n; ++j) {
    const Row known = row(j);
    for (Lower::InnerIterator it(lower, j); it; ++it)
      if (it.row() > j) row(it.row()) -= it.value() * known;
  }
  for (Eigen::Index j = 0; j < n; ++j) row(j) *= 1.0 / diagonal[j];
  for (Eigen::Index j = n - 1; j >= 0; --j) {
    Row value = row(j);
    for (Lower::InnerIterator it(lower, j); it; ++it)
      if (it.row() > j) value -= it.value() * row(it.row());
    row(j) = value;
  }
  rows = factor.permutationPinv() * rows;
}

}  // namespace isocorr
