#include "isocorr/spectral/reduced_laplace_basis.h"

#include <Eigen/Eigenvalues>

#include "isocorr/sampling/vertex_spreading.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

// Jacobi weight of the smoothing step (the classic 2/3 of smoothed aggregation).
constexpr double kSmoothingWeight = 2.0 / 3.0;
// Jacobi steps on the prolonged eigenvectors' residual.
constexpr int kResidualSmoothingSteps = 3;

// Column c is the indicator of centre c's cell: the vertices nearer to it (in edge hops)
// than to any other centre.
SparseMatrix cell_indicators(const TriangleMesh& mesh, const std::vector<int>& centres) {
  const int n = mesh.num_vertices();
  const std::vector<int> owner = nearest_centre(MeshTopology(mesh), n, centres);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(n);
  for (int v = 0; v < n; ++v) entries.emplace_back(v, owner[v], 1.0);
  SparseMatrix indicators(n, static_cast<Eigen::Index>(centres.size()));
  indicators.setFromTriplets(entries.begin(), entries.end());
  return indicators;
}

}  // namespace

LaplaceBasis compute_reduced_laplace_basis(const TriangleMesh& mesh, int k, int reduced_size,
                                           const LaplaceBasisOptions& options) {
  const int n = mesh.num_vertices();
  if (n <= reduced_size) return compute_laplace_basis(mesh, k, options);
  const Eigen::VectorXd mass = lumped_mass(mesh);
  Eigen::Index massless = 0;
  if (mass.minCoeff(&massless) <= 0)
    throw InputError("Laplace-Beltrami basis: vertex " + std::to_string(massless) +
                     " has no area (unreferenced, or only in zero-area faces); clean the mesh first");
  const SparseMatrix stiffness = cotangent_laplacian(mesh);

  // Prolongation U = (I - w D^-1 L) * indicators: rows still sum to 1 (L's rows sum to 0),
  // and each function now falls off smoothly across its cell's border instead of jumping.
  const SparseMatrix indicators = cell_indicators(mesh, spread_vertices(mesh, reduced_size));
  const Eigen::VectorXd inverse_diagonal = stiffness.diagonal().cwiseInverse();
  const SparseMatrix smoothing = SparseMatrix(inverse_diagonal.asDiagonal() * stiffness) * kSmoothingWeight;
  const SparseMatrix prolongation = SparseMatrix(indicators - smoothing * indicators).pruned();

  // The reduced problem, its mass lumped (U's rows sum to 1, so the lumped reduced mass is
  // U^T m and the total area is kept).
  const SparseMatrix reduced_stiffness = SparseMatrix(prolongation.transpose() * stiffness * prolongation).pruned();
  const Eigen::VectorXd reduced_mass = prolongation.transpose() * mass;
  if (reduced_mass.minCoeff() <= 0)
    throw InputError("Laplace-Beltrami basis: a reduced cell has no area; the mesh is too irregular to reduce");
  const LaplaceBasis reduced = laplace_eigenpairs(reduced_stiffness, reduced_mass, k, options);

  // Prolonged vectors span the right space but carry the cells' kinks (on a sphere with
  // 7 vertices per cell: eigenvalues 19% high). A few Jacobi steps on the full residual
  // L phi - lambda M phi smooth the kinks out, and a Rayleigh-Ritz step on the full mesh
  // then rotates within the span to the best eigenvector estimates, in ascending order.
  Eigen::MatrixXd phi = prolongation * reduced.eigenvectors;
  Eigen::VectorXd values = reduced.eigenvalues;
  for (int step = 0; step < kResidualSmoothingSteps; ++step) {
    const Eigen::MatrixXd residual = stiffness * phi - mass.asDiagonal() * phi * values.asDiagonal();
    phi -= kSmoothingWeight * (inverse_diagonal.asDiagonal() * residual);
  }
  const Eigen::MatrixXd projected_stiffness = phi.transpose() * (stiffness * phi);
  const Eigen::MatrixXd projected_mass = phi.transpose() * mass.asDiagonal() * phi;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ritz(projected_stiffness, projected_mass);
  if (ritz.info() != Eigen::Success)
    throw InputError("Laplace-Beltrami basis: the reduced basis is degenerate (Rayleigh-Ritz failed)");

  LaplaceBasis basis;
  basis.mass = mass;
  basis.eigenvectors = phi * ritz.eigenvectors();
  basis.eigenvalues = ritz.eigenvalues();
  normalise_basis(mass, basis.eigenvectors);
  return basis;
}

}  // namespace isocorr
