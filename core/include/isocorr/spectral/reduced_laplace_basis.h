// The Laplace-Beltrami eigenbasis of a large mesh from a smaller problem: the eigenproblem
// is projected onto m smooth, locally supported functions (one per evenly spread vertex:
// its Voronoi cell's indicator, smoothed by one Jacobi step of L), solved there, and the
// eigenvectors are prolonged to every vertex (Galerkin reduction, in the spirit of Nasikun
// et al. 2018, "Fast approximation of Laplace-Beltrami eigenproblems"). Low frequencies,
// the ones ZoomOut uses, are smooth on the scale of the cells, so they survive the
// reduction; the solve costs what a mesh of m vertices costs.
#pragma once

#include "isocorr/mesh/triangle_mesh.h"
#include "isocorr/spectral/laplace_beltrami.h"

namespace isocorr {

// Falls back to compute_laplace_basis when the mesh has no more than `reduced_size`
// vertices. The result is M-orthonormal on the full mesh, with the full mesh's mass.
LaplaceBasis compute_reduced_laplace_basis(const TriangleMesh& mesh, int k, int reduced_size,
                                           const LaplaceBasisOptions& options = {});

}  // namespace isocorr
