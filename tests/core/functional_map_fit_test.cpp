// The functional-map fit on a shape matched to itself, where the true C is the identity.
#include <gtest/gtest.h>

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
  options.threads = 2;
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

}  // namespace
}  // namespace isocorr
