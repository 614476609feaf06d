// The as-rigid-as-possible energy's pieces on the source mesh (Sorkine & Alexa 2007):
// each vertex's one-ring with its cotangent weights, and the best rotation of a ring.
// Shared by the rigidity polish (rigidity_polish.cpp) and the unfolding of mirrored
// segments before it (mirrored_segments.cpp).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

// Deformed positions of the source's vertices, one row each.
using DeformedPoints = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

struct RingEdge {
  int to;
  double weight;
  Vec3 rest;  // the scaled source edge x_from - x_to
};

// Every vertex's one-ring with its weights (compressed rows), and the Laplacian of the
// same weights: the rigidity half of the polish's linear system.
struct Rings {
  std::vector<int> offsets;
  std::vector<RingEdge> edges;
  Eigen::SparseMatrix<double> laplacian;
};

// The rings of `mesh` with its edges scaled by `scale` (source lengths to target lengths).
Rings build_rings(const TriangleMesh& mesh, double scale);

// sum_j w rest_vj (y_v - y_j)^T over v's ring: what the best rotation of v's ring fits.
Eigen::Matrix3d ring_covariance(const Rings& rings, const DeformedPoints& deformed, int v);

// The rotation R minimising sum_j w |(y_i - y_j) - R rest_ij|^2, from the ring's
// covariance, never a reflection.
Eigen::Matrix3d best_rotation(const Eigen::Matrix3d& covariance);

}  // namespace isocorr
