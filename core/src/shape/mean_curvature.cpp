#include "isocorr/shape/mean_curvature.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/SparseCholesky>

#include "isocorr/spectral/laplace_beltrami.h"
#include "isocorr/util/error.h"

namespace isocorr {

namespace {

// Each column of `integrated` (values already multiplied by the lumped mass) diffused at
// every scale by one implicit heat step (M + t L) h = integrated, t = (scale * length)^2;
// returns one V x columns matrix per scale. One factorisation per scale serves every column.
std::vector<Eigen::MatrixXf> diffuse_at_scales(const Eigen::SparseMatrix<double>& stiffness,
                                               const Eigen::VectorXd& mass, const Eigen::MatrixXd& integrated,
                                               const std::vector<double>& scales, double length) {
  std::vector<Eigen::MatrixXf> smoothed;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  Eigen::SparseMatrix<double> system;
  for (size_t j = 0; j < scales.size(); ++j) {
    const double scale_length = scales[j] * length;
    system = scale_length * scale_length * stiffness;
    system.diagonal() += mass;
    if (j == 0) solver.analyzePattern(system);  // one sparsity pattern for every scale
    solver.factorize(system);
    if (solver.info() != Eigen::Success) throw InputError("curvature smoothing: factorisation failed");
    smoothed.push_back(solver.solve(integrated).cast<float>());
  }
  return smoothed;
}

}  // namespace

SmoothedCurvature smoothed_mean_and_gaussian_curvature(const TriangleMesh& mesh, const std::vector<Vec3>& normals,
                                                       const std::vector<double>& scales, double reference_length) {
  const int n = mesh.num_vertices();
  const Eigen::SparseMatrix<double> stiffness = cotangent_laplacian(mesh);
  const Eigen::VectorXd mass = lumped_mass(mesh);
  const double root_area = reference_length > 0 ? reference_length : std::sqrt(mass.sum());
  Eigen::MatrixXd position(n, 3);
  for (int v = 0; v < n; ++v) position.row(v) = mesh.vertices[v].transpose();
  const Eigen::MatrixXd curvature_normal = stiffness * position;  // 2 H n M at each vertex
  // Column 0: M H sqrt(area); column 1: M K area, M K being the angle defect.
  Eigen::MatrixXd integrated(n, 2);
  for (int v = 0; v < n; ++v) integrated(v, 0) = 0.5 * curvature_normal.row(v).dot(normals[v]) * root_area;
  integrated.col(1).setConstant(2 * M_PI);
  for (const int v : boundary_vertices(mesh)) integrated(v, 1) = M_PI;
  for (const Face& f : mesh.faces)
    for (int c = 0; c < 3; ++c) {
      const Vec3 next = mesh.vertices[f[(c + 1) % 3]] - mesh.vertices[f[c]];
      const Vec3 previous = mesh.vertices[f[(c + 2) % 3]] - mesh.vertices[f[c]];
      integrated(f[c], 1) -= std::atan2(next.cross(previous).norm(), next.dot(previous));
    }
  integrated.col(1) *= root_area * root_area;

  const std::vector<Eigen::MatrixXf> smoothed = diffuse_at_scales(stiffness, mass, integrated, scales, root_area);
  SmoothedCurvature result;
  result.mean.resize(n, scales.size());
  result.gaussian.resize(n, scales.size());
  for (size_t j = 0; j < scales.size(); ++j) {
    result.mean.col(j) = smoothed[j].col(0);
    result.gaussian.col(j) = smoothed[j].col(1);
  }
  return result;
}

Eigen::MatrixXf smoothed_mean_curvature(const TriangleMesh& mesh, const std::vector<Vec3>& normals,
                                        const std::vector<double>& scales, double reference_length) {
  return smoothed_mean_and_gaussian_curvature(mesh, normals, scales, reference_length).mean;
}

double curvature_disagreement(const Eigen::MatrixXf& source_curvature, const Eigen::MatrixXf& target_curvature,
                              const std::vector<std::pair<int, int>>& pairs) {
  const int scales = static_cast<int>(std::min(source_curvature.cols(), target_curvature.cols()));
  if (scales == 0 || pairs.empty()) return 0;
  double total = 0;
  for (int j = 0; j < scales; ++j) {
    double difference = 0, size = 0;
    for (const auto& [a, b] : pairs) {
      const double x = source_curvature(a, j), y = target_curvature(b, j);
      difference += std::abs(x - y);
      size += std::abs(x) + std::abs(y);
    }
    total += size > 0 ? difference / size : 0.0;
  }
  return total / scales;
}

}  // namespace isocorr
