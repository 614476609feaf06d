// Maps with known answers for the refinement's tests: how near a map is to the truth, and
// the creature with a smoothly twisted map onto its rotated copy.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/refinement/zoomout.h"
#include "isocorr/shape/preprocessed_shape.h"
#include "isocorr/util/kd_tree.h"
#include "spectral_test_shapes.h"

namespace isocorr::test_support {

// Fraction of `image` equal to `truth`, and of the rest within one ring of it.
inline std::pair<double, double> exact_and_near(const std::vector<int>& image, const std::vector<int>& truth,
                                         const MeshTopology& topology) {
  int exact = 0, near = 0;
  for (size_t v = 0; v < image.size(); ++v) {
    if (image[v] == truth[v]) {
      ++exact;
      continue;
    }
    for (const int* w = topology.neighbours_begin(truth[v]); w != topology.neighbours_end(truth[v]); ++w)
      near += *w == image[v];
  }
  return {static_cast<double>(exact) / image.size(), static_cast<double>(exact + near) / image.size()};
}

// The creature and a rotated copy, with a map that slides the surface smoothly: every image
// taken from a point turned about an axis through the body by an angle growing from 0 to
// `degrees` along the axis (a twist, which stretches some rings and squeezes others).
struct TwistedCopy {
  explicit TwistedCopy(double degrees)
      : blob(limbed_blob(4)),
        copy(rotated_scaled_renumbered(blob, 1.0, 7)),
        source(PreprocessedShape::build(blob, spectral_options())),
        target(PreprocessedShape::build(copy.mesh, spectral_options())),
        points(blob.vertices.begin(), blob.vertices.end()),
        inverse(copy.permutation.size()) {
    std::vector<int> ids(points.size());
    for (size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<int>(i);
    const KdTree tree(points, ids);
    const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 1, 0.2).normalized();
    double low = 1e9, high = -1e9;
    for (const auto& p : points) low = std::min(low, p.dot(axis)), high = std::max(high, p.dot(axis));
    for (int v = 0; v < blob.num_vertices(); ++v) {
      const double angle = degrees * M_PI / 180 * (points[v].dot(axis) - low) / (high - low);
      map.image.push_back(copy.permutation[tree.nearest(Eigen::AngleAxisd(angle, axis) * points[v])]);
    }
    for (size_t v = 0; v < inverse.size(); ++v) inverse[copy.permutation[v]] = static_cast<int>(v);
    map.reverse_image = inverse;
  }
  // Mean distance on the source between a vertex and the preimage of its image.
  double mean_error(const std::vector<int>& image) const {
    double sum = 0;
    for (int v = 0; v < blob.num_vertices(); ++v) sum += (points[inverse[image[v]]] - points[v]).norm();
    return sum / blob.num_vertices();
  }

  TriangleMesh blob;
  RenumberedCopy copy;
  std::shared_ptr<const PreprocessedShape> source, target;
  std::vector<Eigen::Vector3d> points;
  std::vector<int> inverse;  // copy vertex -> blob vertex
  SpectralMap map;
};

}  // namespace isocorr::test_support
