// The largest eigenpairs of a self-adjoint operator by thick-restart block Lanczos.
//
// Why our own and not Spectra's Lanczos: the Laplace-Beltrami basis needs a few hundred
// eigenpairs, and a single-vector Lanczos then spends most of its time orthogonalising each
// new vector against all earlier ones, one matrix-vector product at a time (memory-bound:
// 200 eigenpairs of michael0, 52K vertices, took 19 s, 13 of them in those products). A block
// of vectors is orthogonalised by matrix-matrix products instead, which read the basis once
// for the whole block, and the operator is applied to a block at once.
//
// The method: the Krylov space of the operator from a random block is built block by block,
// each new block orthogonalised against the blocks the recurrence couples it to, then,
// where what it still has along the whole basis exceeds semi-orthogonality, against all
// ("twice is enough"), and then within itself; when
// the basis is full, the Rayleigh-Ritz pairs of the projected matrix are checked, and the
// best of them are kept as the start of the next cycle (thick restart, Wu & Simon 2000, here
// in block form) until the wanted ones have converged.
#pragma once

#include <functional>

#include <Eigen/Core>

namespace isocorr {

// Vectors per block. Eight doubles are two AVX registers, so the kernels that orthogonalise a
// block keep a few rows' partial sums in registers; larger blocks need more operator
// products to converge (200 eigenpairs of a 5K mesh: 503 single vectors, 624 in blocks of 8,
// 768 in blocks of 16).
inline constexpr int kLanczosBlock = 8;

// out = T in, for an n by kLanczosBlock block of vectors.
using BlockOperator = std::function<void(const Eigen::MatrixXd& in, Eigen::MatrixXd& out)>;

struct BlockLanczosOptions {
  // Basis vectors per restart cycle; 0 = twice the count plus two blocks.
  int subspace = 0;
  // A Ritz pair has converged when its residual norm is at most this times its value.
  double tolerance = 1e-10;
  int max_restarts = 1000;
};

struct BlockLanczosResult {
  Eigen::VectorXd values;   // count, descending
  Eigen::MatrixXd vectors;  // n by count, orthonormal in the weighted inner product
  int restarts = 0;
  long products = 0;        // vectors the operator was applied to
};

// The `count` algebraically largest eigenpairs of T, which must be self-adjoint in the inner
// product <x, y> = x^T diag(weights) y (positive weights). Small problems (the basis would
// not fit) are solved densely from T applied to the identity. Deterministic: the start block
// comes from a fixed seed. Throws InputError when count is not in [1, n) or the restarts run
// out.
BlockLanczosResult largest_eigenpairs(const BlockOperator& apply, const Eigen::VectorXd& weights, int count,
                                      const BlockLanczosOptions& options = {});

}  // namespace isocorr
