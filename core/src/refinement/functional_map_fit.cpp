#include "isocorr/refinement/functional_map_fit.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

// Rows per chunk of the normal equations: fits on samples (a few thousand rows) are one
// chunk, summed exactly as a single product.
constexpr Eigen::Index kFitChunkRows = 16384;

// The nearest orthogonal matrix to c: its polar factor U V^T = c (c^T c)^(-1/2), here
// from the symmetric eigendecomposition of c^T c, which takes a third of the time of an
// SVD at k = 150 (2.2 against 6.4 ms; the polish makes 21 fits at k = 100-200). Squaring
// c squares its condition number, so a nearly singular c (a start with too few distinct
// pairs) goes through the SVD. A wide c (fewer source than target functions: a part) gets
// orthonormal rows, from c c^T.
Eigen::MatrixXd nearest_orthogonal(const Eigen::MatrixXd& c) {
  constexpr double kWellConditioned = 1e-8;  // least over largest eigenvalue of c^T c
  const bool wide = c.rows() < c.cols();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(wide ? Eigen::MatrixXd(c * c.transpose())
                                                                  : Eigen::MatrixXd(c.transpose() * c));
  if (eigen.info() == Eigen::Success) {
    const Eigen::VectorXd& values = eigen.eigenvalues();  // ascending
    if (values(0) > kWellConditioned * values(values.size() - 1)) {
      const Eigen::MatrixXd& vectors = eigen.eigenvectors();
      const Eigen::MatrixXd inverse_root = vectors * values.cwiseSqrt().cwiseInverse().asDiagonal() * vectors.transpose();
      return wide ? Eigen::MatrixXd(inverse_root * c) : Eigen::MatrixXd(c * inverse_root);
    }
  }
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(c, Eigen::ComputeThinU | Eigen::ComputeThinV);
  return svd.matrixU() * svd.matrixV().transpose();
}

// Column j of c solves (normal + diag(added.col(j))) c_j = rhs_j, `normal` holding its lower
// triangle. By conjugate gradients with the diagonal as preconditioner, all columns of a
// chunk at once (their products are one matrix product): `normal` is nearly diagonal
// (evenly spread samples of mass-orthonormal functions) and the term adds to the diagonal
// only, so the preconditioned systems have condition numbers of about 2 (FAUST 5k at
// k = 200; about 12 on every vertex of an uneven mesh) and 15-50 iterations reach the
// Cholesky solution to 1e-15. One factorisation per column took k^4 / 3 per fit, most of
// the polish's fits (k = 100-200): 82 -> 14 ms at k = 200 on one core. A column that does
// not converge (a nearly singular fit from few pairs) is solved by its Cholesky factor.
// The chunks are fixed, so the result does not depend on the number of workers.
void solve_commuting_columns(const Eigen::MatrixXd& normal, const Eigen::MatrixXd& added, const Eigen::MatrixXd& rhs,
                             int threads, Eigen::MatrixXd& c) {
  constexpr int kChunkColumns = 32;
  constexpr int kMaxIterations = 150;
  constexpr double kTolerance = 1e-13;  // residual norm relative to the right side's
  enum class Column { kIterating, kConverged, kByFactor };
  const Eigen::Index k = normal.rows();
  const Eigen::MatrixXd full = normal.selfadjointView<Eigen::Lower>();
  const int chunks = static_cast<int>((k + kChunkColumns - 1) / kChunkColumns);
  parallel_for(chunks, threads, [&](int chunk, int) {
    const Eigen::Index first = chunk * kChunkColumns, cols = std::min<Eigen::Index>(kChunkColumns, k - first);
    const auto term = added.middleCols(first, cols);
    const Eigen::MatrixXd inverse_diagonal = (term.colwise() + full.diagonal()).cwiseInverse();
    Eigen::MatrixXd x = Eigen::MatrixXd::Zero(k, cols), r = rhs.middleCols(first, cols);
    Eigen::MatrixXd z = inverse_diagonal.cwiseProduct(r), p = z, q(k, cols);
    Eigen::VectorXd rz = r.cwiseProduct(z).colwise().sum().transpose();
    const Eigen::VectorXd limit = kTolerance * r.colwise().norm().transpose();
    std::vector<Column> state(cols, Column::kIterating);
    int iterating = 0;
    for (Eigen::Index j = 0; j < cols; ++j) {
      if (limit(j) > 0) ++iterating;
      else state[j] = Column::kConverged;  // a zero right side: x = 0
    }
    for (int iteration = 0; iteration < kMaxIterations && iterating > 0; ++iteration) {
      q.noalias() = full * p;
      q += term.cwiseProduct(p);
      for (Eigen::Index j = 0; j < cols; ++j) {
        if (state[j] != Column::kIterating) continue;
        const double curvature = p.col(j).dot(q.col(j));
        if (!(curvature > 0)) {  // broken down (or NaN)
          state[j] = Column::kByFactor;
          --iterating;
          continue;
        }
        const double alpha = rz(j) / curvature;
        x.col(j) += alpha * p.col(j);
        r.col(j) -= alpha * q.col(j);
        if (r.col(j).norm() <= limit(j)) {
          state[j] = Column::kConverged;
          --iterating;
          continue;
        }
        z.col(j) = inverse_diagonal.col(j).cwiseProduct(r.col(j));
        const double next = r.col(j).dot(z.col(j));
        p.col(j) = z.col(j) + (next / rz(j)) * p.col(j);
        rz(j) = next;
      }
    }
    for (Eigen::Index j = 0; j < cols; ++j) {
      if (state[j] == Column::kConverged) {
        c.col(first + j) = x.col(j);
        continue;
      }
      // Positive definite: a Cholesky factor without pivoting does.
      Eigen::MatrixXd system = full;
      system.diagonal() += term.col(j);
      c.col(first + j) = system.llt().solve(rhs.col(first + j));
    }
  });
}

}  // namespace

// Why the commutativity term: an isometry's functional map only mixes eigenfunctions of
// (nearly) equal eigenvalue. A map with local errors puts weight on entries that mix
// distant frequencies; the term pulls those towards 0 without touching the near-diagonal
// blocks. Measured on SCAPE 000->001..005: D_grd 0.0099 without it, 0.0093 with weight 10
// (and more mirrored FAUST maps: see ZoomOutOptions::commutativity).
//
// Why the projection: the functional map of an isometry between area-normalised,
// mass-orthonormal bases is orthogonal; the plain least-squares C is not when some pairs
// are wrong: wrong pairs are uncorrelated with the rest and shrink C towards 0 by their
// share, and shrunk queries then favour small-norm rows in the nearest-neighbour search,
// a bias the iterations never leave (measured: 81% exact on a perfect copy from a start
// with a quarter of the pairs wrong, against exact with the projection).
Eigen::MatrixXf fit_functional_map(const SpectralRowsView& a, const SpectralRowsView& b, const FunctionalMapFit& fit) {
  const int k = static_cast<int>(a.cols());
  const int target_k = static_cast<int>(b.cols());
  // The normal equations summed over chunks of kFitChunkRows rows, the chunks on workers
  // side by side: on every vertex of a 52K mesh at k = 200 the products took 0.4 s on one
  // core while the other waited. Only the lower triangles are formed and read (the product
  // as a symmetric rank-k update, half a full product's work).
  const Eigen::Index rows = a.rows();
  const int chunks = static_cast<int>(std::max<Eigen::Index>(1, (rows + kFitChunkRows - 1) / kFitChunkRows));
  std::vector<Eigen::MatrixXd> normals(chunks), rhss(chunks);
  auto normal_of = [&](const Eigen::MatrixXd& ad, int chunk) {
    normals[chunk] = Eigen::MatrixXd::Zero(k, k);
    normals[chunk].selfadjointView<Eigen::Lower>().rankUpdate(ad.transpose());
  };
  if (chunks == 1) {
    // A fit on samples (one chunk): its two products side by side, the same sums as one
    // after the other (the polish's 31 fits on 2000 samples each left a core idle). The
    // right side costs twice the normal matrix (a full product against a symmetric one), so
    // the worker that forms the normal matrix also takes its first `split` columns, about a
    // quarter: 3.3 -> 2.5 ms per fit at k = 200. Column blocks of a multiple of 8 are
    // summed exactly as in the whole product (Eigen blocks the inner dimension by its
    // length alone).
    const Eigen::MatrixXd ad = a.cast<double>();
    const Eigen::MatrixXd bd = b.cast<double>();
    const Eigen::Index split = std::max<Eigen::Index>(0, (2 * target_k - k) / 4) / 8 * 8;
    rhss[0].resize(k, target_k);
    parallel_for(2, fit.threads, [&](int task, int) {
      if (task == 0) {
        normal_of(ad, 0);
        rhss[0].leftCols(split).noalias() = ad.transpose() * bd.leftCols(split);
      } else {
        rhss[0].rightCols(target_k - split).noalias() = ad.transpose() * bd.rightCols(target_k - split);
      }
    });
  } else {
    parallel_for(chunks, fit.threads, [&](int chunk, int) {
      const Eigen::Index begin = chunk * kFitChunkRows, count = std::min(kFitChunkRows, rows - begin);
      const Eigen::MatrixXd ad = a.middleRows(begin, count).cast<double>();
      const Eigen::MatrixXd bd = b.middleRows(begin, count).cast<double>();
      normal_of(ad, chunk);
      rhss[chunk] = ad.transpose() * bd;
    });
  }
  Eigen::MatrixXd normal = std::move(normals[0]), rhs = std::move(rhss[0]);
  for (int chunk = 1; chunk < chunks; ++chunk) normal += normals[chunk], rhs += rhss[chunk];
  normal.diagonal().array() += 1e-9 * std::max(1.0, normal.diagonal().maxCoeff());
  Eigen::MatrixXd c(k, target_k);
  const bool commute = k == target_k && fit.commutativity > 0 && fit.source_eigenvalues && fit.target_eigenvalues &&
                       fit.source_eigenvalues->size() >= k && fit.target_eigenvalues->size() >= k && k > 1;
  if (commute) {
    const Eigen::ArrayXd source_values = fit.source_eigenvalues->head(k).cast<double>().array();
    const Eigen::ArrayXd target_values = fit.target_eigenvalues->head(k).cast<double>().array();
    const double largest = std::max(1e-12, target_values(k - 1));
    const double weight = fit.commutativity * static_cast<double>(a.rows()) / (largest * largest);
    // Column j of C solves its own system: the term only adds to the diagonal.
    Eigen::MatrixXd added(k, k);
    for (int j = 0; j < k; ++j) added.col(j) = weight * (source_values - target_values(j)).square();
    solve_commuting_columns(normal, added, rhs, fit.threads, c);
  } else {
    c = normal.llt().solve(rhs);
  }
  // A part's k source functions against a whole's target_k (target_k / k = the whole's area
  // over the part's, by Weyl's law): each whole function restricted to the part keeps about
  // unit norm on the part's normalised area, so C's columns have norm about 1 and its rows
  // about sqrt(target_k / k).
  const double row_norm = std::sqrt(static_cast<double>(std::max(k, target_k)) / k);
  return (row_norm * nearest_orthogonal(c)).cast<float>();
}

}  // namespace isocorr
