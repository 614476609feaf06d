// The functional map of a set of point pairs: the k x k' matrix C with a[i] C ~ b[i], where
// a[i] and b[i] are the rows of the source and target eigenbases at pair i (k' = k between
// complete shapes; k < k' from a part to a whole, partial_refinement.h).
#pragma once

#include <Eigen/Core>

namespace isocorr {

using SpectralRows = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
// Rows of a SpectralRows or of a block of its first columns, without a copy.
using SpectralRowsView = Eigen::Ref<const SpectralRows, 0, Eigen::OuterStride<>>;

struct FunctionalMapFit {
  // Eigenvalues of both bases (first k used; area-scaled like the bases). When both are
  // given and `commutativity` > 0, the fit also asks C to commute with the Laplacians.
  const Eigen::VectorXf* source_eigenvalues = nullptr;
  const Eigen::VectorXf* target_eigenvalues = nullptr;
  double commutativity = 0;
  // Workers for the normal equations of a fit on many rows (every vertex of a large mesh).
  // The rows are summed in fixed chunks, so the result does not depend on this.
  int threads = 1;
};

// Least squares (normal equations in double, a tiny ridge so that a rank-deficient start
// still solves), plus, with eigenvalues, the Laplacian commutativity term
//   commutativity * n * sum_ij ((lambda_S,i - lambda_T,j) / lambda_T,k)^2 C_ij^2
// (n pairs, so the weight does not depend on how many pairs there are; lambda_T,k, the
// largest eigenvalue used, makes it scale-free; square C only), then the nearest orthogonal
// matrix (for k < k', sqrt(k' / k) times the nearest one with orthonormal rows).
Eigen::MatrixXf fit_functional_map(const SpectralRowsView& a, const SpectralRowsView& b,
                                   const FunctionalMapFit& fit = {});

}  // namespace isocorr
