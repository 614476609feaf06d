#include "isocorr/spectral/laplace_beltrami.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>

#include "isocorr/spectral/block_lanczos.h"
#include "isocorr/spectral/row_chunked_product.h"
#include "isocorr/util/ldlt_row_solve.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

// A deflated pass's eigenvalue counts as a missed copy when it lies below the k-th found one
// by more than this (relative): equal values are interchangeable copies, and the solver's
// tolerance is far smaller.
constexpr double kMissedEigenvalueGap = 1e-6;

// (L - sigma M)^-1 x for a whole Lanczos block in one sweep of the factor (ldlt_row_solve.h):
// the per-column solves were a third of the eigensolve on 52K vertices.
Eigen::MatrixXd solve_block(const Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower>& factor,
                            const Eigen::MatrixXd& x) {
  if (x.cols() != kLanczosBlock) return factor.solve(x);
  Eigen::Matrix<double, Eigen::Dynamic, kLanczosBlock, Eigen::RowMajor> rows = x;
  solve_rows_in_place(factor, rows);
  return rows;
}

// A deflated pass needs room for a Lanczos run of its own beside the k found vectors.
constexpr int kDeflationRoom = 40;

// Y = P (L - sigma M)^-1 M P X, the shift-invert operator, by a sparse Cholesky of
// L - sigma M (positive definite for sigma < 0). It is self-adjoint in the M inner product,
// and its largest eigenvalues 1 / (lambda - sigma) belong to the smallest lambda.
// P = I - Phi Phi^T M projects out the eigenvectors found so far (none at first),
// M-orthogonally so that the operator stays self-adjoint.
class ShiftedCholeskySolve {
 public:
  ShiftedCholeskySolve(const SparseMatrix& stiffness, const Eigen::VectorXd& mass, double sigma,
                       const JobControl* control)
      : mass_(mass), control_(control) {
    factor_.compute(stiffness - sigma * SparseMatrix(mass.asDiagonal()));
    if (factor_.info() != Eigen::Success || factor_.vectorD().minCoeff() <= 0) {
      throw InputError("Laplace-Beltrami basis: L - sigma M is not positive definite (sigma = " +
                       std::to_string(sigma) + "); the mesh is too degenerate");
    }
  }

  void deflate(const Eigen::MatrixXd& found) {
    found_ = found;
    mass_found_ = mass_.asDiagonal() * found;
  }

  void apply(const Eigen::MatrixXd& x, Eigen::MatrixXd& y) const {
    if (control_) control_->check_cancelled();
    if (found_.cols() == 0) {
      y = solve_block(factor_, mass_.asDiagonal() * x);
      return;
    }
    // Both sides: the found vectors are eigenvectors only to the solver's tolerance, and the
    // solve amplifies what is left of the low ones by up to lambda_k / |sigma|.
    y = solve_block(factor_, mass_.asDiagonal() * x - mass_found_ * (mass_found_.transpose() * x));
    y -= found_ * (mass_found_.transpose() * y);
  }

 private:
  const Eigen::VectorXd& mass_;
  const JobControl* control_;
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> factor_;
  Eigen::MatrixXd found_, mass_found_;  // Phi and M Phi
};

struct Eigenpairs {
  Eigen::VectorXd values;   // ascending
  Eigen::MatrixXd vectors;
};

// The `count` eigenpairs of the (deflated) pencil nearest sigma, ascending.
Eigenpairs lanczos(const ShiftedCholeskySolve& shifted_inverse, const Eigen::VectorXd& mass, int count,
                   double sigma, const LaplaceBasisOptions& options) {
  BlockLanczosOptions lanczos_options;
  lanczos_options.tolerance = options.tolerance;
  lanczos_options.max_restarts = options.max_restarts;
  BlockLanczosResult result = largest_eigenpairs(
      [&](const Eigen::MatrixXd& x, Eigen::MatrixXd& y) { shifted_inverse.apply(x, y); }, mass, count,
      lanczos_options);
  // theta = 1 / (lambda - sigma): descending theta is ascending lambda.
  return {(1.0 / result.values.array() + sigma).matrix(), std::move(result.vectors)};
}

// Two found eigenvalues (past the constant one) that coincide to within the missed-copy gap.
bool has_repeated_eigenvalue(const Eigen::VectorXd& ascending) {
  for (Eigen::Index i = 2; i < ascending.size(); ++i)
    if (ascending[i] - ascending[i - 1] <= kMissedEigenvalueGap * std::abs(ascending[i])) return true;
  return false;
}

// Phi <- Phi G^(-1/2) with G = Phi^T M Phi (Loewdin): M-orthonormal, and the nearest such
// basis to what the solver returned, so well-separated eigenvectors are left as they are.
void make_mass_orthonormal(const Eigen::VectorXd& mass, Eigen::MatrixXd& phi) {
  const Eigen::MatrixXd gram = phi.transpose() * mass.asDiagonal() * phi;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
  multiply_by_row_chunks(phi, Eigen::MatrixXd(eigen.operatorInverseSqrt()), phi);  // in place
}

// Largest-magnitude entry positive (first such entry on exact ties).
void fix_signs(Eigen::MatrixXd& phi) {
  for (Eigen::Index c = 0; c < phi.cols(); ++c) {
    Eigen::Index largest = 0;
    phi.col(c).cwiseAbs().maxCoeff(&largest);
    if (phi(largest, c) < 0) phi.col(c) *= -1;
  }
}

}  // namespace

SparseMatrix cotangent_laplacian(const TriangleMesh& mesh) {
  // Why the floor on the area: the cotangent at a vertex is (e1 . e2) / (2 A). In a sliver
  // (an angle near 0 or 180 degrees) 2A -> 0 and the weights blow up; one weight of 1e8
  // beside weights of order 1 makes L - sigma M too ill-conditioned to factor. Clamping
  // each cotangent separately would be wrong: in a flat sliver two cotangents go to +inf
  // and one to -inf, and clipping them independently gives a triangle whose element matrix
  // is indefinite (L would no longer be positive semi-definite). Instead the triangle's
  // common denominator 2A is floored at sum|e|^2 / (2 kMaxCotangent): the element matrix is
  // the Gram matrix of the edge vectors over 4A, so it stays positive semi-definite for any
  // positive denominator, and |e1 . e2| <= sum|e|^2 / 2 bounds every |cot| by
  // kMaxCotangent. Only slivers are affected (a smallest angle under about 0.06 degrees
  // in an isosceles one); they carry no area worth speaking of, so the mass is left exact.
  const int n = mesh.num_vertices();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(12 * mesh.faces.size());
  for (const Face& f : mesh.faces) {
    const Vec3& p0 = mesh.vertices[f[0]];
    const Vec3& p1 = mesh.vertices[f[1]];
    const Vec3& p2 = mesh.vertices[f[2]];
    const double squared_edges =
        (p1 - p0).squaredNorm() + (p2 - p1).squaredNorm() + (p0 - p2).squaredNorm();
    const double twice_area = std::max((p1 - p0).cross(p2 - p0).norm(),
                                       squared_edges / (2 * kMaxCotangent));
    if (!(twice_area > 0)) continue;  // all three corners coincide: no edge directions
    for (int corner = 0; corner < 3; ++corner) {
      const int i = f[corner], j = f[(corner + 1) % 3], k = f[(corner + 2) % 3];
      const Vec3& pi = mesh.vertices[i];
      const double cot = (mesh.vertices[j] - pi).dot(mesh.vertices[k] - pi) / twice_area;
      const double w = cot / 2;  // this corner's half of the weight of the opposite edge jk
      entries.emplace_back(j, k, -w);
      entries.emplace_back(k, j, -w);
      entries.emplace_back(j, j, w);
      entries.emplace_back(k, k, w);
    }
  }
  SparseMatrix laplacian(n, n);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  return laplacian;
}

Eigen::VectorXd lumped_mass(const TriangleMesh& mesh) {
  const std::vector<double> areas = vertex_areas(mesh);
  return Eigen::Map<const Eigen::VectorXd>(areas.data(), static_cast<Eigen::Index>(areas.size()));
}

LaplaceBasis compute_laplace_basis(const TriangleMesh& mesh, int k,
                                   const LaplaceBasisOptions& options) {
  if (mesh.num_vertices() < 2) throw InputError("Laplace-Beltrami basis: the mesh needs at least 2 vertices");
  const Eigen::VectorXd mass = lumped_mass(mesh);
  Eigen::Index massless = 0;
  if (mass.minCoeff(&massless) <= 0) {
    throw InputError("Laplace-Beltrami basis: vertex " + std::to_string(massless) +
                     " has no area (unreferenced, or only in zero-area faces); clean the mesh first");
  }
  return laplace_eigenpairs(cotangent_laplacian(mesh), mass, k, options);
}

LaplaceBasis laplace_eigenpairs(const Eigen::SparseMatrix<double>& stiffness, const Eigen::VectorXd& lumped,
                                int k, const LaplaceBasisOptions& options) {
  const int n = static_cast<int>(stiffness.rows());
  if (k < 1) throw InputError("Laplace-Beltrami basis: k must be at least 1, got " + std::to_string(k));
  if (n < 2) throw InputError("Laplace-Beltrami basis: the problem needs at least 2 unknowns");
  k = std::min(k, n - 1);

  LaplaceBasis basis;
  basis.mass = lumped;
  const double sigma = -options.relative_shift * stiffness.diagonal().sum() / basis.mass.sum();

  ShiftedCholeskySolve shifted_inverse(stiffness, basis.mass, sigma, options.control);
  Eigenpairs pairs = lanczos(shifted_inverse, basis.mass, k, sigma, options);
  // Block Lanczos finds at most one vector per eigenspace per block column in exact
  // arithmetic (kLanczosBlock of them); further copies of a multiple eigenvalue only appear
  // through round-off, and convergence may be declared without them. Symmetric meshes hit
  // it (an icosphere's l = 4 eigenvalue has 9 copies; single-vector Lanczos already missed
  // the third l = 1 copy at k = 4). So look again with the found vectors projected out: an
  // eigenvalue below the k-th is a missed copy. One eigenpair per pass. Skipped when the
  // complement is too small for a Lanczos run of its own (k close to #V), and when no two
  // found eigenvalues coincide: an exactly repeated eigenvalue needs an exact symmetry of
  // order 3 or more (rotations of a sphere, a square grid), and such a symmetry repeats many
  // eigenvalues, so a missed copy never comes alone. Scanned and remeshed shapes have none,
  // and skip the check's short run.
  const bool room_to_check = n - k >= kDeflationRoom;
  const bool repeated = has_repeated_eigenvalue(pairs.values);
  for (int pass = 0; options.complete_multiplets && room_to_check && repeated && pass < k; ++pass) {
    make_mass_orthonormal(basis.mass, pairs.vectors);
    shifted_inverse.deflate(pairs.vectors);
    const Eigenpairs missed = lanczos(shifted_inverse, basis.mass, 1, sigma, options);
    const double limit = pairs.values[k - 1] - kMissedEigenvalueGap * std::abs(pairs.values[k - 1]);
    const int below = static_cast<int>((missed.values.array() < limit).count());
    if (below == 0) break;
    Eigenpairs merged{Eigen::VectorXd(k + below), Eigen::MatrixXd(n, k + below)};
    merged.values << pairs.values, missed.values.head(below);
    merged.vectors << pairs.vectors, missed.vectors.leftCols(below);
    std::vector<int> order(k + below);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return merged.values[a] < merged.values[b]; });
    for (int i = 0; i < k; ++i) {
      pairs.values[i] = merged.values[order[i]];
      pairs.vectors.col(i) = merged.vectors.col(order[i]);
    }
  }
  basis.eigenvalues = std::move(pairs.values);
  basis.eigenvectors = std::move(pairs.vectors);
  normalise_basis(basis.mass, basis.eigenvectors);
  return basis;
}

void normalise_basis(const Eigen::VectorXd& mass, Eigen::MatrixXd& eigenvectors) {
  make_mass_orthonormal(mass, eigenvectors);
  fix_signs(eigenvectors);
}

}  // namespace isocorr
