// The reduced eigenproblem against the full one on a mesh with a known spectrum.
#include "isocorr/spectral/reduced_laplace_basis.h"

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"

namespace isocorr {
namespace {

TEST(ReducedLaplaceBasis, LowFrequenciesMatchTheFullProblem) {
  // Unit sphere, 10242 vertices reduced to 1500 cells: eigenvalues l(l+1), l <= 3.
  const TriangleMesh sphere = icosphere(5);
  const LaplaceBasis full = compute_laplace_basis(sphere, 16);
  const LaplaceBasis reduced = compute_reduced_laplace_basis(sphere, 16, 1500);
  ASSERT_EQ(reduced.eigenvectors.rows(), sphere.num_vertices());
  ASSERT_EQ(reduced.eigenvectors.cols(), 16);
  // M-orthonormal on the full mesh.
  const Eigen::MatrixXd gram = reduced.eigenvectors.transpose() * reduced.mass.asDiagonal() * reduced.eigenvectors;
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(16, 16)).cwiseAbs().maxCoeff(), 1e-8);
  // A Galerkin reduction only raises eigenvalues; measured within 1% here, allowed 3%.
  for (int i = 1; i < 16; ++i) {
    EXPECT_GE(reduced.eigenvalues[i], full.eigenvalues[i] * (1 - 1e-6)) << i;
    EXPECT_LT(reduced.eigenvalues[i], full.eigenvalues[i] * 1.03) << i;
  }
  // Each multiplet spans the same space: the projection of the reduced vectors of l = 1..3
  // onto the full ones keeps their norm.
  const Eigen::MatrixXd overlap =
      full.eigenvectors.transpose() * full.mass.asDiagonal() * reduced.eigenvectors;  // 16 x 16
  for (int i = 0; i < 16; ++i) EXPECT_GT(overlap.col(i).norm(), 0.99) << i;
}

TEST(ReducedLaplaceBasis, SmallMeshesAreSolvedInFull) {
  const TriangleMesh sphere = icosphere(3);
  const LaplaceBasis reduced = compute_reduced_laplace_basis(sphere, 9, 5000);
  const LaplaceBasis full = compute_laplace_basis(sphere, 9);
  EXPECT_LT((reduced.eigenvalues - full.eigenvalues).cwiseAbs().maxCoeff(), 1e-9);
}

}  // namespace
}  // namespace isocorr
