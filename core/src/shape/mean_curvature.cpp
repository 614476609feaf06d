#include "isocorr/shape/mean_curvature.h"

#include <algorithm>
#include <cmath>

#include <Eigen/SparseCholesky>

#include "isocorr/spectral/laplace_beltrami.h"
#include "isocorr/util/error.h"

namespace isocorr {

Eigen::MatrixXf smoothed_mean_curvature(const TriangleMesh& mesh, const std::vector<Vec3>& normals,
                                        const std::vector<double>& scales, double reference_length) {
  const int n = mesh.num_vertices();
  const Eigen::SparseMatrix<double> stiffness = cotangent_laplacian(mesh);
  const Eigen::VectorXd mass = lumped_mass(mesh);
  const double root_area = reference_length > 0 ? reference_length : std::sqrt(mass.sum());
  Eigen::MatrixXd position(n, 3);
  for (int v = 0; v < n; ++v) position.row(v) = mesh.vertices[v].transpose();
  const Eigen::MatrixXd curvature_normal = stiffness * position;  // 2 H n M at each vertex
  Eigen::VectorXd weighted(n);  // M H sqrt(area): the right-hand side of every smoothing
  for (int v = 0; v < n; ++v) weighted(v) = 0.5 * curvature_normal.row(v).dot(normals[v]) * root_area;

  Eigen::MatrixXf result(n, scales.size());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  Eigen::SparseMatrix<double> system;
  for (size_t j = 0; j < scales.size(); ++j) {
    const double length = scales[j] * root_area;
    system = length * length * stiffness;
    system.diagonal() += mass;
    if (j == 0) solver.analyzePattern(system);  // one sparsity pattern for every scale
    solver.factorize(system);
    if (solver.info() != Eigen::Success) throw InputError("mean curvature smoothing: factorisation failed");
    result.col(j) = solver.solve(weighted).cast<float>();
  }
  return result;
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
