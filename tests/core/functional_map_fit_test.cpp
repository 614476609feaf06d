// The functional-map fit: on a shape matched to itself, where the true C is the identity,
// and on many random rows, where the answer is a least-squares fit made orthogonal.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <Eigen/SVD>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/refinement/functional_map_fit.h"
#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {
namespace {

constexpr int kBasis = 40;

std::shared_ptr<const PreprocessedShape> blob_with_basis() {
  PreprocessOptions options;
  options.spectral_basis = kBasis;
  options.spectral_samples = 400;
  return PreprocessedShape::build(limbed_blob(3), options);
}

// The first `count` vertices' rows: fewer pairs than basis functions, so the pairs alone
// leave C undetermined.
SpectralRows first_rows(const PreprocessedShape& shape, int count) {
  return shape.spectral_basis().topRows(count).leftCols(kBasis);
}

TEST(FunctionalMapFit, CommutativityDeterminesAnUnderdeterminedFit) {
  const auto shape = blob_with_basis();
  const SpectralRows rows = first_rows(*shape, 25);
  const Eigen::MatrixXf identity = Eigen::MatrixXf::Identity(kBasis, kBasis);

  const Eigen::MatrixXf plain = fit_functional_map(rows, rows);
  EXPECT_GT((plain - identity).norm(), 1.0) << "25 pairs should not determine a 40 x 40 map by themselves";

  FunctionalMapFit fit;
  fit.source_eigenvalues = fit.target_eigenvalues = &shape->spectral_eigenvalues();
  fit.commutativity = 10;
  const Eigen::MatrixXf commuting = fit_functional_map(rows, rows, fit);
  EXPECT_LT((commuting - identity).norm(), 0.05);
}

// rows x cols entries drawn from the standard normal distribution.
SpectralRows normal_rows(int rows, int cols, std::mt19937& random) {
  std::normal_distribution<float> normal;
  SpectralRows m(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) m(i, j) = normal(random);
  return m;
}

// A random rows x cols matrix with orthonormal columns (cols <= rows).
Eigen::MatrixXd orthonormal_columns(int rows, int cols, std::mt19937& random) {
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(normal_rows(rows, cols, random).cast<double>());
  return Eigen::MatrixXd(qr.householderQ()).leftCols(cols);
}

// Pairs that carry almost nothing of one basis function leave the least-squares C nearly
// singular (here R diag(1e-7, 1, ..., 1) R^T, R a rotation); its nearest orthogonal matrix
// is still the identity. The fast polar factor squares C's condition number, so such a C
// must go through the SVD.
TEST(FunctionalMapFit, ANearlySingularFitStillGivesTheNearestOrthogonalMap) {
  constexpr int kRows = 2000, kColumns = 12;
  std::mt19937 random(11);
  const SpectralRows source = normal_rows(kRows, kColumns, random);
  const Eigen::MatrixXd rotation = orthonormal_columns(kColumns, kColumns, random);
  Eigen::VectorXd scales = Eigen::VectorXd::Ones(kColumns);
  scales(0) = 1e-7;
  const SpectralRows target =
      source * (rotation * scales.asDiagonal() * rotation.transpose()).cast<float>();
  const Eigen::MatrixXf c = fit_functional_map(source, target);
  EXPECT_LT((c - Eigen::MatrixXf::Identity(kColumns, kColumns)).norm(), 1e-4);
}

TEST(FunctionalMapFit, WeightDoesNotDependOnTheEigenvaluesScale) {
  const auto shape = blob_with_basis();
  const SpectralRows rows = first_rows(*shape, 25);
  const Eigen::VectorXf scaled = shape->spectral_eigenvalues() * 7.f;
  FunctionalMapFit fit;
  fit.source_eigenvalues = fit.target_eigenvalues = &shape->spectral_eigenvalues();
  fit.commutativity = 1;
  const Eigen::MatrixXf original = fit_functional_map(rows, rows, fit);
  fit.source_eigenvalues = fit.target_eigenvalues = &scaled;
  EXPECT_LT((fit_functional_map(rows, rows, fit) - original).norm(), 1e-3);
}

// A fit on every vertex of a large mesh sums its rows in chunks on several workers: it
// gives the least-squares map over all rows made orthogonal, bit for bit the same on one
// worker.
TEST(FunctionalMapFit, ManyRowsFitTheSameOnAnyNumberOfWorkers) {
  constexpr int kRows = 40000, kColumns = 12;
  std::mt19937 random(7);
  std::normal_distribution<float> normal;
  SpectralRows source(kRows, kColumns), noise(kRows, kColumns);
  for (int i = 0; i < kRows; ++i)
    for (int j = 0; j < kColumns; ++j) source(i, j) = normal(random), noise(i, j) = 0.3f * normal(random);
  Eigen::MatrixXf permutation = Eigen::MatrixXf::Zero(kColumns, kColumns);
  for (int j = 0; j < kColumns; ++j) permutation((j * 5) % kColumns, j) = j % 2 == 0 ? 1.f : -1.f;
  const SpectralRows target = source * permutation + noise;

  const Eigen::MatrixXd a = source.cast<double>(), b = target.cast<double>();
  const Eigen::MatrixXd least_squares = (a.transpose() * a).ldlt().solve(a.transpose() * b);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(least_squares, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::MatrixXf expected = (svd.matrixU() * svd.matrixV().transpose()).cast<float>();

  FunctionalMapFit fit;
  fit.threads = 1;
  const Eigen::MatrixXf alone = fit_functional_map(source, target, fit);
  fit.threads = 2;
  const Eigen::MatrixXf shared = fit_functional_map(source, target, fit);
  EXPECT_LT((alone - expected).norm(), 1e-5);
  EXPECT_GT((alone - permutation).norm(), 1e-4) << "the noise should move the fit off the permutation";
  EXPECT_TRUE(alone == shared);
}

// The commutativity fit by its definition: each column of C by its own Cholesky factor of
// the normal matrix plus that column's diagonal term, then the nearest orthogonal matrix.
Eigen::MatrixXf commuting_fit_by_factors(const SpectralRows& source, const SpectralRows& target,
                                         const Eigen::VectorXf& eigenvalues, double commutativity) {
  const int k = static_cast<int>(source.cols());
  const Eigen::MatrixXd a = source.cast<double>(), b = target.cast<double>();
  Eigen::MatrixXd normal = a.transpose() * a;
  normal.diagonal().array() += 1e-9 * std::max(1.0, normal.diagonal().maxCoeff());
  const Eigen::MatrixXd rhs = a.transpose() * b;
  const Eigen::ArrayXd values = eigenvalues.head(k).cast<double>().array();
  const double weight = commutativity * static_cast<double>(a.rows()) / (values(k - 1) * values(k - 1));
  Eigen::MatrixXd c(k, k);
  for (int j = 0; j < k; ++j) {
    Eigen::MatrixXd system = normal;
    system.diagonal().array() += weight * (values - values(j)).square();
    c.col(j) = system.llt().solve(rhs.col(j));
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(c, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return (svd.matrixU() * svd.matrixV().transpose()).cast<float>();
}

// The commutativity term's column systems are solved by conjugate gradients, and by their
// Cholesky factors where those do not converge: on many noisy pairs (well conditioned) and
// on fewer pairs than functions (the normal matrix is singular but for its ridge), the fit
// is the factors' one, bit for bit the same on any number of workers.
TEST(FunctionalMapFit, CommutingColumnsSolveAsByTheirFactors) {
  constexpr int kColumns = 70;
  const Eigen::VectorXf eigenvalues = Eigen::VectorXf::LinSpaced(kColumns, 0.f, 400.f);
  std::mt19937 random(3);
  for (const int rows : {2000, 50}) {
    const SpectralRows source = normal_rows(rows, kColumns, random);
    Eigen::MatrixXf permutation = Eigen::MatrixXf::Zero(kColumns, kColumns);
    for (int j = 0; j < kColumns; ++j) permutation((j + (j % 3 == 0 ? 1 : 0)) % kColumns, j) = 1.f;
    const SpectralRows target = source * permutation + 0.5f * normal_rows(rows, kColumns, random);
    FunctionalMapFit fit;
    fit.source_eigenvalues = fit.target_eigenvalues = &eigenvalues;
    fit.commutativity = 10;
    fit.threads = 1;
    const Eigen::MatrixXf alone = fit_functional_map(source, target, fit);
    fit.threads = 2;
    const Eigen::MatrixXf shared = fit_functional_map(source, target, fit);
    const Eigen::MatrixXf expected = commuting_fit_by_factors(source, target, eigenvalues, 10);
    EXPECT_LT((alone - expected).norm(), 1e-4) << rows << " rows";
    EXPECT_GT((alone - Eigen::MatrixXf::Identity(kColumns, kColumns)).norm(), 1.0) << "the term should not decide alone";
    EXPECT_TRUE(alone == shared) << rows << " rows";
  }
}

// From a part (12 functions) to a whole (20): C is wide, sqrt(20 / 12) times a matrix with
// orthonormal rows, and the fit gives it back from noise-free pairs.
TEST(FunctionalMapFit, APartsWideMapComesBackWithRowsOfTheWholesNorm) {
  constexpr int kRows = 3000, kPart = 12, kWhole = 20;
  std::mt19937 random(5);
  const SpectralRows source = normal_rows(kRows, kPart, random);
  const Eigen::MatrixXd orthonormal_rows = orthonormal_columns(kWhole, kPart, random).transpose();
  const Eigen::MatrixXd expected = std::sqrt(double(kWhole) / kPart) * orthonormal_rows;
  const SpectralRows target = source * expected.cast<float>();
  const Eigen::MatrixXf c = fit_functional_map(source, target);
  ASSERT_EQ(c.rows(), kPart);
  ASSERT_EQ(c.cols(), kWhole);
  EXPECT_LT((c.cast<double>() - expected).norm(), 1e-4);
  EXPECT_LT((c * c.transpose() - (float(kWhole) / kPart) * Eigen::MatrixXf::Identity(kPart, kPart)).norm(), 1e-4);

  // One row scaled far down (C C^T's condition below the fast path's bound, so the SVD
  // decides): the nearest map is the same, to within the floats' rounding of that row.
  Eigen::VectorXd scales = Eigen::VectorXd::Ones(kPart);
  scales(0) = 5e-5;
  const SpectralRows squeezed = source * (scales.asDiagonal() * expected).cast<float>();
  EXPECT_LT((fit_functional_map(source, squeezed).cast<double>() - expected).norm(), 1e-2);
}

}  // namespace
}  // namespace isocorr
