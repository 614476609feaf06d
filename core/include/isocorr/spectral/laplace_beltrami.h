// The Laplace-Beltrami operator of a triangle mesh (cotangent stiffness, lumped mass) and
// its low-frequency eigenbasis: the functional basis ZoomOut refines a pointwise map in.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "isocorr/mesh/triangle_mesh.h"
#include "isocorr/util/progress.h"

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

struct LaplaceBasisOptions {
  // The shift-invert solver factors L - sigma M with sigma = -relative_shift * trace(L) /
  // area, a fraction of the typical (high-frequency) eigenvalue: L - sigma M is then
  // positive definite with a condition number near 1 / relative_shift, whatever the mesh
  // size or units, while sigma stays far below the first non-zero eigenvalue.
  double relative_shift = 1e-8;
  // Restarts of the Lanczos iteration and its relative tolerance on each Ritz value.
  int max_restarts = 1000;
  double tolerance = 1e-10;
  // Lanczos can miss copies of an exactly repeated eigenvalue (symmetric meshes: spheres,
  // grids); when true and some found eigenvalues coincide, a deflated pass looks for them
  // and swaps them in. Costs one short Lanczos run when nothing was missed; a mesh without
  // coinciding eigenvalues skips it.
  bool complete_multiplets = true;
  // Checked at every linear solve (a large mesh takes seconds to minutes); may be null.
  const JobControl* control = nullptr;
};

// The first k eigenpairs of L phi = lambda M phi, ascending.
struct LaplaceBasis {
  Eigen::VectorXd eigenvalues;   // k, ascending; the first is 0 up to round-off
  Eigen::MatrixXd eigenvectors;  // #V by k, M-orthonormal: Phi^T diag(mass) Phi = I
  Eigen::VectorXd mass;          // #V, the lumped mass M
};

// Computes the basis by shift-invert block Lanczos (block_lanczos.h) with a sparse Cholesky
// of L - sigma M (Eigen's SimplicialLDLT, its triangular solves done a block at a time. On
// 52K vertices it factors in 0.07 s; CHOLMOD's supernodal LLT was slower to factor, 0.13 s,
// and whole runs with its simplicial LDLT stayed within the noise of a shared machine, so
// it is not worth a dependency). 200 eigenpairs of michael0 (52K vertices) take 7 s, of
// which the Gram-Schmidt products are most.
// k is capped at #V - 1. Each eigenvector's largest-magnitude entry is positive, so the
// result does not depend on the solver's start. Throws InputError for k < 1, for a vertex
// without area (unreferenced, or only in zero-area faces: clean the mesh first) and when
// the solver does not converge.
LaplaceBasis compute_laplace_basis(const TriangleMesh& mesh, int k,
                                   const LaplaceBasisOptions& options = {});

// The same for any stiffness matrix (symmetric positive semi-definite, rows summing to 0)
// with a diagonal mass: what compute_laplace_basis solves, and what a reduced problem
// (reduced_laplace_basis.h) solves on fewer unknowns.
LaplaceBasis laplace_eigenpairs(const Eigen::SparseMatrix<double>& stiffness, const Eigen::VectorXd& mass, int k,
                                const LaplaceBasisOptions& options = {});

// Makes `eigenvectors` M-orthonormal (the nearest such basis) with each column's
// largest-magnitude entry positive, as both solvers return them.
void normalise_basis(const Eigen::VectorXd& mass, Eigen::MatrixXd& eigenvectors);

}  // namespace isocorr
