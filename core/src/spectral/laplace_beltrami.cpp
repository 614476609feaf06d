#include "isocorr/spectral/laplace_beltrami.h"

#include <algorithm>
#include <vector>

#include <Eigen/Geometry>

namespace isocorr {

using SparseMatrix = Eigen::SparseMatrix<double>;

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

}  // namespace isocorr
