#include "isocorr/spectral/block_lanczos.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <Eigen/Eigenvalues>

#include "isocorr/spectral/row_chunked_product.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

using Matrix = Eigen::MatrixXd;
using Vector = Eigen::VectorXd;
// The basis, one row per unknown: the kernels below stream each row once per block.
using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using Block = Eigen::Matrix<double, Eigen::Dynamic, kLanczosBlock, Eigen::RowMajor>;
// One row of a block: two AVX registers, so four rows' partial sums stay in registers.
using BlockRow = Eigen::Matrix<double, kLanczosBlock, 1>;

// A new vector whose norm falls below this share of its norm before orthogonalisation lies
// in the span of the basis (an invariant subspace was found): it is replaced by a random
// direction, so that the basis keeps growing.
constexpr double kDependentShare = 1e-10;
// A new vector may lean on the basis by up to this (the square root of the rounding unit)
// before it is orthogonalised again.
const double kSemiOrthogonality = std::sqrt(std::numeric_limits<double>::epsilon());
// Guards the lean's quotient for a column that the local pass left at zero.
constexpr double kTiny = 1e-300;
constexpr unsigned kStartSeed = 20191;
// Random directions drawn for one missing basis vector before the operator is declared broken:
// a sane operator leaves a random direction outside the basis with probability one.
constexpr int kRandomDirectionTries = 16;
// Residuals within this many rounding units of the operator's norm count as converged.
constexpr double kResidualRounding = 10;
// Rows rotated at a time by a thick restart (the rotation is done in place, chunk by chunk).
constexpr Eigen::Index kRestartRows = 256;

// out(c, :) += sum over the rows r of [i, i + rows) of V(r, c) weights[r] w(r, :), for c in
// [first, cols), with rows 4 (the partial sums then fill the vector registers) or 1.
void add_projection_of_rows(const RowMajorMatrix& v, Eigen::Index first, Eigen::Index cols, const Vector& weights,
                            const Block& w, Eigen::Index i, int rows, Block& out) {
  auto out_row = [&](Eigen::Index c) { return Eigen::Map<BlockRow>(out.row(c).data()); };
  auto weighted_row = [&](Eigen::Index r) { return BlockRow(weights[r] * w.row(r).transpose()); };
  if (rows == 1) {
    const BlockRow y = weighted_row(i);
    const double* vi = v.row(i).data();
    for (Eigen::Index c = first; c < cols; ++c) out_row(c) += vi[c] * y;
    return;
  }
  const BlockRow y0 = weighted_row(i), y1 = weighted_row(i + 1), y2 = weighted_row(i + 2), y3 = weighted_row(i + 3);
  const double* v0 = v.row(i).data();
  const double* v1 = v.row(i + 1).data();
  const double* v2 = v.row(i + 2).data();
  const double* v3 = v.row(i + 3).data();
  for (Eigen::Index c = first; c < cols; ++c) out_row(c) += v0[c] * y0 + v1[c] * y1 + v2[c] * y2 + v3[c] * y3;
}

// out = V(:, first:cols)^T diag(weights) w in rows [first, cols) of out (cols by
// kLanczosBlock, zero above `first`). Eigen's general product would first copy V into its
// packed layout for an eight-column right side, which costs as much as the product itself;
// here V is read once and `out` stays in the L1 cache.
void weighted_projection(const RowMajorMatrix& v, Eigen::Index first, Eigen::Index cols, const Vector& weights,
                         const Block& w, Block& out) {
  const Eigen::Index n = v.rows();
  out.setZero(cols, kLanczosBlock);
  Eigen::Index i = 0;
  for (; i + 4 <= n; i += 4) add_projection_of_rows(v, first, cols, weights, w, i, 4, out);
  for (; i < n; ++i) add_projection_of_rows(v, first, cols, weights, w, i, 1, out);
}

// w -= V(:, first:cols) coefficients(first:cols, :). With `projection`, also projection =
// V(:, 0:cols)^T diag(weights) w of the new w, each row's part taken while the row is still
// in cache: the rows of V are read from memory once for both.
void subtract_combination(const RowMajorMatrix& v, Eigen::Index first, Eigen::Index cols, const Block& coefficients,
                          Block& w, const Vector& weights, Block* projection = nullptr) {
  const Eigen::Index n = v.rows();
  if (projection) projection->setZero(cols, kLanczosBlock);
  auto coefficient_row = [&](Eigen::Index c) { return Eigen::Map<const BlockRow>(coefficients.row(c).data()); };
  auto w_row = [&](Eigen::Index i) { return Eigen::Map<BlockRow>(w.row(i).data()); };
  Eigen::Index i = 0;
  for (; i + 4 <= n; i += 4) {
    BlockRow s0 = BlockRow::Zero(), s1 = BlockRow::Zero(), s2 = BlockRow::Zero(), s3 = BlockRow::Zero();
    const double* v0 = v.row(i).data();
    const double* v1 = v.row(i + 1).data();
    const double* v2 = v.row(i + 2).data();
    const double* v3 = v.row(i + 3).data();
    for (Eigen::Index c = first; c < cols; ++c) {
      const BlockRow k = coefficient_row(c);
      s0 += v0[c] * k;
      s1 += v1[c] * k;
      s2 += v2[c] * k;
      s3 += v3[c] * k;
    }
    w_row(i) -= s0;
    w_row(i + 1) -= s1;
    w_row(i + 2) -= s2;
    w_row(i + 3) -= s3;
    if (projection) add_projection_of_rows(v, 0, cols, weights, w, i, 4, *projection);
  }
  for (; i < n; ++i) {
    BlockRow sum = BlockRow::Zero();
    const double* vi = v.row(i).data();
    for (Eigen::Index c = first; c < cols; ++c) sum += vi[c] * coefficient_row(c);
    w_row(i) -= sum;
    if (projection) add_projection_of_rows(v, 0, cols, weights, w, i, 1, *projection);
  }
}

// A basis orthonormal in the weighted inner product, grown a block at a time.
class WeightedBasis {
 public:
  WeightedBasis(const Vector& weights, Eigen::Index capacity)
      : weights_(weights), vectors_(weights.size(), capacity) {}

  Eigen::Index size() const { return size_; }
  // V(:, 0:coefficients.rows()) coefficients (row_chunked_product.h: no left-side copy).
  Matrix combination(const Matrix& coefficients) const {
    Matrix out(vectors_.rows(), coefficients.cols());
    multiply_by_row_chunks(vectors_.leftCols(coefficients.rows()), coefficients, out);
    return out;
  }
  Matrix column_block(Eigen::Index begin) const { return vectors_.middleCols(begin, kLanczosBlock); }

  // Orthonormalises `block` against the basis and within itself and appends it. On return
  // the old block equals basis * against + new block * within (`against` size() by b,
  // `within` b by b upper triangular).
  void append(Block block, Eigen::Index local_first, Block& against, Matrix& within, std::mt19937& random) {
    constexpr int b = kLanczosBlock;
    Vector norms_before(b);
    for (int j = 0; j < b; ++j) norms_before[j] = weighted_norm(block.col(j));
    against.setZero(size_, b);
    // Classical Gram-Schmidt, the second pass only where it is needed. The first pass
    // projects on the columns from `local_first` on only: a Lanczos product's large
    // coefficients lie on its own block and the one before it (on every kept vector after a
    // restart, where local_first is 0). What the block still has along the whole basis is
    // measured while that subtraction has the rows in cache, and subtracted (a second read of
    // the basis) only when it exceeds semi-orthogonality, which is all Lanczos needs for Ritz
    // pairs accurate to rounding (Simon 1984). A block left leaning by round-off (1e-9) has
    // the next product lean by far more, 1e-2 (the shifted inverse amplifies the converged
    // directions), so about every other block is read once: 200 eigenpairs of michael0
    // 3.87 -> 3.65 s, eigenvalues equal to 4e-13, eigenvectors to 3e-8.
    if (size_ > 0) {
      Block first, second;
      weighted_projection(vectors_, local_first, size_, weights_, block, first);
      subtract_combination(vectors_, local_first, size_, first, block, weights_, &second);
      against = first;
      double loss = 0;
      for (int j = 0; j < b; ++j)
        loss = std::max(loss, second.col(j).norm() / std::max(weighted_norm(block.col(j)), kTiny * norms_before[j]));
      if (loss > kSemiOrthogonality) {
        subtract_combination(vectors_, 0, size_, second, block, weights_);
        against += second;
        // A column that lost more to the full pass than it kept may still lean on the basis
        // (the test of Daniel, Gragg, Kaufman and Stewart): once more, then.
        bool again = false;
        for (int j = 0; j < b; ++j)
          again = again || second.col(j).squaredNorm() > weighted_dot(block.col(j), block.col(j));
        if (again) {
          Block third;
          weighted_projection(vectors_, 0, size_, weights_, block, third);
          subtract_combination(vectors_, 0, size_, third, block, weights_);
          against += third;
        }
      }
    }
    // Within the block, by modified Gram-Schmidt (twice) on contiguous columns.
    Matrix columns = block;
    within.setZero(b, b);
    for (int j = 0; j < b; ++j) {
      for (int pass = 0; pass < 2; ++pass) {
        for (int i = 0; i < j; ++i) {
          const double c = weighted_dot(columns.col(i), columns.col(j));
          columns.col(j) -= c * columns.col(i);
          within(i, j) += c;
        }
      }
      const double norm = weighted_norm(columns.col(j));
      if (norm > kDependentShare * norms_before[j]) {
        within(j, j) = norm;
        columns.col(j) /= norm;
      } else {
        // What was left is round-off: its coupling is dropped, and a random direction
        // orthogonal to everything so far takes its place.
        columns.col(j) = random_orthogonal(columns, j, random);
      }
    }
    vectors_.middleCols(size_, b) = columns;
    size_ += b;
  }

  // Thick restart: the first `kept` vectors become V(:, 0:m) rotation, followed by the
  // current last block. Done in place, a chunk of rows at a time.
  void restart(Eigen::Index m, const Matrix& rotation) {
    const Eigen::Index kept = rotation.cols(), n = vectors_.rows();
    const RowMajorMatrix next = vectors_.middleCols(size_ - kLanczosBlock, kLanczosBlock);
    RowMajorMatrix chunk;
    for (Eigen::Index begin = 0; begin < n; begin += kRestartRows) {
      const Eigen::Index rows = std::min(kRestartRows, n - begin);
      chunk.noalias() = vectors_.block(begin, 0, rows, m) * rotation;
      vectors_.block(begin, 0, rows, kept) = chunk;
    }
    vectors_.middleCols(kept, kLanczosBlock) = next;
    size_ = kept + kLanczosBlock;
  }

 private:
  template <class A, class B>
  double weighted_dot(const A& x, const B& y) const {
    return (x.cwiseProduct(weights_).cwiseProduct(y)).sum();
  }
  template <class A>
  double weighted_norm(const A& x) const {
    return std::sqrt(weighted_dot(x, x));
  }

  // A random unit vector orthogonal to the basis and to the first `count` columns of `block`.
  // Throws NumericalError when none is found: the basis or the weights are not finite.
  Vector random_orthogonal(const Matrix& block, int count, std::mt19937& random) const {
    std::uniform_real_distribution<double> uniform(-1, 1);
    for (int attempt = 0; attempt < kRandomDirectionTries; ++attempt) {
      Block candidate = Block::Zero(weights_.size(), kLanczosBlock);
      for (Eigen::Index i = 0; i < candidate.rows(); ++i) candidate(i, 0) = uniform(random);
      Block coefficients;
      for (int pass = 0; pass < 2; ++pass) {
        if (size_ > 0) {
          weighted_projection(vectors_, 0, size_, weights_, candidate, coefficients);
          subtract_combination(vectors_, 0, size_, coefficients, candidate, weights_);
        }
        for (int i = 0; i < count; ++i)
          candidate.col(0) -= weighted_dot(block.col(i), candidate.col(0)) * block.col(i);
      }
      const double norm = weighted_norm(candidate.col(0));
      if (norm > kDependentShare && std::isfinite(norm)) return candidate.col(0) / norm;
    }
    throw NumericalError("eigensolver: no random direction stays independent of the basis; its vectors are not finite");
  }

  const Vector& weights_;
  RowMajorMatrix vectors_;
  Eigen::Index size_ = 0;
};

// The whole operator from its action on the identity, symmetrised in the weighted inner
// product (D^1/2 T D^-1/2 is symmetric), and solved densely.
BlockLanczosResult dense_eigenpairs(const BlockOperator& apply, const Vector& weights, int count) {
  const Eigen::Index n = weights.size();
  Matrix t(n, n);
  apply(Matrix::Identity(n, n), t);
  const Vector root = weights.cwiseSqrt();
  Matrix symmetric = root.asDiagonal() * t * root.cwiseInverse().asDiagonal();
  symmetric = (symmetric + symmetric.transpose()).eval() / 2;
  const Eigen::SelfAdjointEigenSolver<Matrix> eigen(symmetric);
  BlockLanczosResult result;
  result.values = eigen.eigenvalues().tail(count).reverse();
  result.vectors = root.cwiseInverse().asDiagonal() * eigen.eigenvectors().rightCols(count).rowwise().reverse();
  result.products = n;
  return result;
}

}  // namespace

BlockLanczosResult largest_eigenpairs(const BlockOperator& apply, const Vector& weights, int count,
                                      const BlockLanczosOptions& options) {
  constexpr int b = kLanczosBlock;
  const Eigen::Index n = weights.size();
  if (count < 1 || count >= n)
    throw InputError("eigensolver: asked for " + std::to_string(count) + " eigenpairs of an operator of size " +
                     std::to_string(n));
  // The cycle's basis m, a whole number of blocks, and the pairs `kept` at a restart, with
  // m - kept a whole number of blocks too: about half of the unwanted pairs are kept, as
  // ARPACK keeps them, so the wanted ones converge at the rate of the gap to the discarded.
  const int wanted_subspace = options.subspace > 0 ? options.subspace : 2 * count + 2 * b;
  const Eigen::Index m = b * std::max((count + b) / b + 1, (wanted_subspace + b - 1) / b);
  if (!weights.allFinite() || weights.minCoeff() <= 0)
    throw NumericalError("eigensolver: the inner product's weights are not all finite and positive");
  if (m + b > n) return dense_eigenpairs(apply, weights, count);
  const Eigen::Index kept = m - b * std::max<Eigen::Index>(1, (m - count) / 2 / b);

  std::mt19937 random(kStartSeed);
  WeightedBasis basis(weights, m + b);
  // projected(:, c) holds the coefficients of T v_c in the basis.
  Matrix projected = Matrix::Zero(m + b, m);
  Block against;
  Matrix within;
  {
    std::uniform_real_distribution<double> uniform(-1, 1);
    Block start(n, b);
    for (Eigen::Index i = 0; i < n; ++i)
      for (int j = 0; j < b; ++j) start(i, j) = uniform(random);
    basis.append(start, 0, against, within, random);
  }
  BlockLanczosResult result;
  Eigen::Index done = 0;  // basis vectors whose products are in `projected`
  Eigen::Index cycle_start = 0;  // the kept vectors of the last restart
  Matrix product(n, b);
  for (;;) {
    while (done < m) {
      apply(basis.column_block(done), product);
      result.products += b;
      if (!product.allFinite()) throw NumericalError("eigensolver: the operator produced a non-finite value");
      const Eigen::Index rows = basis.size();
      // The three-term recurrence: the product couples to its own block and the one before,
      // except the first block of a cycle, which couples to every kept vector.
      const Eigen::Index local_first = done > cycle_start ? done - b : 0;
      basis.append(product, local_first, against, within, random);
      projected.block(0, done, rows, b) = against;
      projected.block(rows, done, b, b) = within;
      done += b;
    }
    Matrix symmetric = projected.topRows(m);
    symmetric = (symmetric + symmetric.transpose()).eval() / 2;
    const Eigen::SelfAdjointEigenSolver<Matrix> ritz(symmetric);  // ascending
    const Matrix& y = ritz.eigenvectors();
    // T V y = theta V y + V_next (coupling y): the residual norm of each Ritz pair.
    const Matrix coupling = projected.bottomRows(b) * y;
    // A residual is measured to the rounding of the products, about machine epsilon times
    // the operator's norm (the largest Ritz value); below that it cannot be asked for, which
    // matters for eigenvalues near zero only.
    const double rounding = kResidualRounding * std::numeric_limits<double>::epsilon() *
                            ritz.eigenvalues().cwiseAbs().maxCoeff();
    bool converged = true;
    for (int i = 0; i < count && converged; ++i) {
      const Eigen::Index r = m - 1 - i;
      converged = coupling.col(r).norm() <= std::max(options.tolerance * std::abs(ritz.eigenvalues()[r]), rounding);
    }
    if (converged) {
      result.values = ritz.eigenvalues().tail(count).reverse();
      result.vectors = basis.combination(y.rightCols(count).rowwise().reverse());
      return result;
    }
    if (++result.restarts > options.max_restarts)
      throw InputError("eigensolver: no convergence after " + std::to_string(options.max_restarts) +
                       " restarts (" + std::to_string(result.products) + " operator products)");
    basis.restart(m, y.rightCols(kept));
    projected.setZero();
    projected.topLeftCorner(kept, kept) = ritz.eigenvalues().tail(kept).asDiagonal();
    projected.block(kept, 0, b, kept) = coupling.rightCols(kept);
    done = kept;
    cycle_start = kept;
  }
}

}  // namespace isocorr
