// The block Lanczos eigensolver on operators with known spectra: weighted inner products,
// repeated eigenvalues, an operator of low rank (the basis meets an invariant subspace),
// and the dense path for small problems.
#include "isocorr/spectral/block_lanczos.h"

#include <limits>
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

// T = D^-1 A for a symmetric A: self-adjoint in the inner product weighted by D.
struct WeightedOperator {
  Eigen::MatrixXd a;
  Eigen::VectorXd weights;
  BlockOperator op() const {
    return [this](const Eigen::MatrixXd& x, Eigen::MatrixXd& y) { y = weights.cwiseInverse().asDiagonal() * (a * x); };
  }
};

// A symmetric matrix with the given eigenvalues and random eigenvectors, and random weights.
WeightedOperator random_operator(const Eigen::VectorXd& eigenvalues, unsigned seed) {
  const Eigen::Index n = eigenvalues.size();
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(0.5, 2.0);
  Eigen::MatrixXd g(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) g(i, j) = uniform(random) - 1.25;
  const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(g).householderQ();
  WeightedOperator t;
  t.weights.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) t.weights[i] = uniform(random);
  // A symmetric S with the eigenvalues, then A = D^1/2 S D^1/2, so that D^-1 A is similar to S.
  const Eigen::MatrixXd s = q * eigenvalues.asDiagonal() * q.transpose();
  const Eigen::VectorXd root = t.weights.cwiseSqrt();
  t.a = root.asDiagonal() * s * root.asDiagonal();
  return t;
}

void expect_eigenpairs(const WeightedOperator& t, const BlockLanczosResult& result, const Eigen::VectorXd& expected,
                       double tolerance) {
  ASSERT_EQ(result.values.size(), expected.size());
  for (Eigen::Index i = 0; i < expected.size(); ++i) EXPECT_NEAR(result.values[i], expected[i], tolerance) << i;
  const Eigen::MatrixXd gram = result.vectors.transpose() * t.weights.asDiagonal() * result.vectors;
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(gram.rows(), gram.cols())).cwiseAbs().maxCoeff(), 1e-8);
  Eigen::MatrixXd image;
  t.op()(result.vectors, image);
  const Eigen::MatrixXd residual = image - result.vectors * result.values.asDiagonal();
  EXPECT_LT(residual.cwiseAbs().maxCoeff(), tolerance);
}

TEST(BlockLanczos, FindsTheLargestEigenpairsInAWeightedInnerProduct) {
  const int n = 400, count = 30;
  Eigen::VectorXd eigenvalues(n);
  for (int i = 0; i < n; ++i) eigenvalues[i] = 1.0 / (1 + i);  // a shift-invert-like spectrum
  const WeightedOperator t = random_operator(eigenvalues, 7);
  const BlockLanczosResult result = largest_eigenpairs(t.op(), t.weights, count);
  EXPECT_GT(result.products, 0);
  expect_eigenpairs(t, result, eigenvalues.head(count), 1e-8);
}

TEST(BlockLanczos, FindsEveryCopyOfARepeatedEigenvalue) {
  // Six copies of the largest eigenvalue and five of the next: fewer than a block each.
  const int n = 300;
  Eigen::VectorXd eigenvalues(n);
  for (int i = 0; i < n; ++i) eigenvalues[i] = i < 6 ? 10.0 : i < 11 ? 5.0 : 1.0 / i;
  const WeightedOperator t = random_operator(eigenvalues, 11);
  const BlockLanczosResult result = largest_eigenpairs(t.op(), t.weights, 14);
  expect_eigenpairs(t, result, eigenvalues.head(14), 1e-8);
}

TEST(BlockLanczos, KeepsGrowingPastAnInvariantSubspace) {
  // Rank 12: the Krylov space of a block of 8 is exhausted after two blocks, and the basis
  // must go on with fresh directions to return the zero eigenvalues asked for.
  const int n = 200, count = 20;
  Eigen::VectorXd eigenvalues = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < 12; ++i) eigenvalues[i] = 12 - i;
  const WeightedOperator t = random_operator(eigenvalues, 3);
  const BlockLanczosResult result = largest_eigenpairs(t.op(), t.weights, count);
  expect_eigenpairs(t, result, eigenvalues.head(count), 1e-8);
}

TEST(BlockLanczos, SmallProblemsAreSolvedDenselyWithTheSameAnswer) {
  const int n = 40;
  Eigen::VectorXd eigenvalues(n);
  for (int i = 0; i < n; ++i) eigenvalues[i] = n - i;
  const WeightedOperator t = random_operator(eigenvalues, 5);
  const BlockLanczosResult result = largest_eigenpairs(t.op(), t.weights, 20);  // basis would not fit
  EXPECT_EQ(result.products, n);
  EXPECT_EQ(result.restarts, 0);
  expect_eigenpairs(t, result, eigenvalues.head(20), 1e-9);
}

TEST(BlockLanczos, CountOutsideTheOperatorIsAnInputError) {
  const WeightedOperator t = random_operator(Eigen::VectorXd::LinSpaced(10, 1, 10), 1);
  EXPECT_THROW(largest_eigenpairs(t.op(), t.weights, 0), InputError);
  EXPECT_THROW(largest_eigenpairs(t.op(), t.weights, 10), InputError);
}

TEST(BlockLanczos, RunningOutOfRestartsIsAnInputError) {
  const int n = 400;
  Eigen::VectorXd eigenvalues(n);
  for (int i = 0; i < n; ++i) eigenvalues[i] = 1.0 / (1 + i);
  const WeightedOperator t = random_operator(eigenvalues, 9);
  BlockLanczosOptions options;
  options.max_restarts = 0;
  options.tolerance = 1e-15;
  EXPECT_THROW(largest_eigenpairs(t.op(), t.weights, 30, options), InputError);
}

// An operator that overflows or weights that are not finite end the solve with an error,
// never a loop: a mesh scaled to the limits of double once spun here for ever.
TEST(BlockLanczos, NonFiniteOperatorOrWeightsAreAnErrorNotALoop) {
  const Eigen::VectorXd weights = Eigen::VectorXd::Ones(200);
  const BlockOperator overflowing = [](const Eigen::MatrixXd& x, Eigen::MatrixXd& y) {
    y = x * std::numeric_limits<double>::infinity();
  };
  EXPECT_THROW(largest_eigenpairs(overflowing, weights, 10), NumericalError);
  const BlockOperator identity = [](const Eigen::MatrixXd& x, Eigen::MatrixXd& y) { y = x; };
  Eigen::VectorXd broken = weights;
  broken[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(largest_eigenpairs(identity, broken, 10), NumericalError);
  broken[3] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(largest_eigenpairs(identity, broken, 10), NumericalError);
}

}  // namespace
}  // namespace isocorr
