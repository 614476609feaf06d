#include "isocorr/mesh/coordinate_normalisation.h"

#include <cmath>

#include "isocorr/util/error.h"

namespace isocorr {

Vec3 CoordinateNormalisation::to_input(const Vec3& normalised) const {
  Vec3 input;
  for (int a = 0; a < 3; ++a) input[a] = std::ldexp(normalised[a] + offset[a], -exponent);
  return input;
}

double length_ratio_in_files(double normalised_ratio, const CoordinateNormalisation& source,
                             const CoordinateNormalisation& target) {
  return std::ldexp(normalised_ratio, target.exponent - source.exponent);
}

double length_ratio_normalised(double ratio_in_files, const CoordinateNormalisation& source,
                               const CoordinateNormalisation& target) {
  return std::ldexp(ratio_in_files, source.exponent - target.exponent);
}

CoordinateNormalisation normalise_coordinates(std::vector<Vec3>& points) {
  if (points.empty()) throw InputError("the mesh has no vertices");
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) {
    if (!p.allFinite()) throw InputError("a vertex has a non-finite coordinate");
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  // Halves first: hi - lo itself overflows for coordinates near the largest double.
  const Vec3 half_extent = hi / 2 - lo / 2;
  const double largest = half_extent.maxCoeff();
  if (!(largest > 0)) throw InputError("all vertices of the mesh coincide");
  CoordinateNormalisation normalisation;
  int exponent = 0;
  std::frexp(largest, &exponent);  // largest = f 2^exponent, f in [0.5, 1)
  normalisation.exponent = -exponent;
  for (Vec3& p : points)
    for (int a = 0; a < 3; ++a) p[a] = std::ldexp(p[a], normalisation.exponent);
  const double scaled_largest = std::ldexp(largest, normalisation.exponent);
  for (int a = 0; a < 3; ++a) {
    const double centre = std::ldexp(lo[a] / 2 + hi[a] / 2, normalisation.exponent);
    if (std::abs(centre) >= 2 * scaled_largest) normalisation.offset[a] = centre;
  }
  if (normalisation.offset != Vec3::Zero())
    for (Vec3& p : points) p -= normalisation.offset;
  return normalisation;
}

}  // namespace isocorr
