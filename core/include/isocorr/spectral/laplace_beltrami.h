// The Laplace-Beltrami operator of a triangle mesh: cotangent stiffness and lumped mass.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

// Cotangent stiffness matrix, #V by #V, symmetric positive semi-definite: off-diagonal
// entry (i, j) is -(cot a + cot b) / 2 for the angles a, b opposite edge ij, the diagonal
// makes every row sum to 0. Boundary edges have one opposite angle only, which is the
// natural (Neumann) boundary condition. Slivers are made harmless as described in the
// source: no |cot| exceeds kMaxCotangent, and L stays positive semi-definite.
inline constexpr double kMaxCotangent = 1000;
Eigen::SparseMatrix<double> cotangent_laplacian(const TriangleMesh& mesh);

// Lumped (barycentric) mass, #V: a third of the area of the faces around each vertex; sums
// to the surface area.
Eigen::VectorXd lumped_mass(const TriangleMesh& mesh);

}  // namespace isocorr
