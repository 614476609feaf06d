// Preprocessing options shared by the tests of spectral refinement (a basis and sample
// count small enough for the procedural meshes), and the mirror images those tests pit
// against the true map.
#pragma once

#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr::test_support {

inline PreprocessOptions spectral_options() {
  PreprocessOptions options;
  options.spectral_basis = 60;
  options.spectral_samples = 800;
  return options;
}

// The vertex of `mesh` nearest to the mirror image of vertex v through the plane x = 0.
inline int x_mirror_of(const TriangleMesh& mesh, int v) {
  const Vec3 reflected(-mesh.vertices[v].x(), mesh.vertices[v].y(), mesh.vertices[v].z());
  int best = 0;
  for (int w = 0; w < mesh.num_vertices(); ++w)
    if ((mesh.vertices[w] - reflected).squaredNorm() < (mesh.vertices[best] - reflected).squaredNorm()) best = w;
  return best;
}

}  // namespace isocorr::test_support
