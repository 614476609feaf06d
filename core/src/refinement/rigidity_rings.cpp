#include "rigidity_rings.h"

#include <algorithm>

#include <Eigen/LU>  // determinant
#include <Eigen/SVD>

#include "isocorr/spectral/laplace_beltrami.h"

namespace isocorr {
namespace {

// Cotangent weights below this are raised to it. An obtuse triangle gives an edge a
// negative weight, which rewards stretching that edge and turns the local best rotation
// into a bad one (TOSCA 5k cat0 -> cat1: D_grd 0.0217 -> 0.040 with raw weights, 0.0208
// with clamped ones); the small positive floor keeps every edge in the energy.
constexpr double kMinEdgeWeight = 0.01;

}  // namespace

Rings build_rings(const TriangleMesh& mesh, double scale) {
  const Eigen::SparseMatrix<double> cotangent = cotangent_laplacian(mesh);  // symmetric
  const int n = mesh.num_vertices();
  Rings rings;
  rings.offsets.assign(n + 1, 0);
  std::vector<Eigen::Triplet<double>> triplets;
  for (int i = 0; i < n; ++i) {
    for (Eigen::SparseMatrix<double>::InnerIterator entry(cotangent, i); entry; ++entry) {
      const int j = static_cast<int>(entry.row());
      if (j == i) continue;
      const double weight = std::max(kMinEdgeWeight, -entry.value());
      rings.edges.push_back({j, weight, scale * (mesh.vertices[i] - mesh.vertices[j])});
      triplets.emplace_back(i, j, -weight);
      triplets.emplace_back(i, i, weight);
    }
    rings.offsets[i + 1] = static_cast<int>(rings.edges.size());
  }
  rings.laplacian.resize(n, n);
  rings.laplacian.setFromTriplets(triplets.begin(), triplets.end());
  return rings;
}

Eigen::Matrix3d ring_covariance(const Rings& rings, const DeformedPoints& deformed, int v) {
  const Vec3 y = deformed.row(v).transpose();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int e = rings.offsets[v]; e < rings.offsets[v + 1]; ++e) {
    const RingEdge& ring = rings.edges[e];
    covariance += ring.weight * ring.rest * (y - deformed.row(ring.to).transpose()).transpose();
  }
  return covariance;
}

Eigen::Matrix3d best_rotation(const Eigen::Matrix3d& covariance) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d v = svd.matrixV();
  if ((v * svd.matrixU().transpose()).determinant() < 0) v.col(2) *= -1;
  return v * svd.matrixU().transpose();
}

}  // namespace isocorr
