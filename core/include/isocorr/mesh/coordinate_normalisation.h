// Brings a mesh's coordinates into a fixed range before anything numeric sees them, so that a
// shape stored in any unit (or at any offset) is computed on as the same numbers.
#pragma once

#include <vector>

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

// normalised = input * 2^exponent - offset: a similarity that rounds no coordinate (but those
// below 2^-1022 of the extent, which carry no geometry).
struct CoordinateNormalisation {
  int exponent = 0;
  Vec3 offset = Vec3::Zero();

  Vec3 to_input(const Vec3& normalised) const;
};

// A ratio of source lengths to target lengths (a part's scale kappa) between normalised meshes,
// given in the files' units, and back: each mesh has its own power of two.
double length_ratio_in_files(double normalised_ratio, const CoordinateNormalisation& source,
                             const CoordinateNormalisation& target);
double length_ratio_normalised(double ratio_in_files, const CoordinateNormalisation& source,
                               const CoordinateNormalisation& target);

// Scales `points` by the power of two that brings the bounding box's largest half-extent into
// [0.5, 1), then moves each axis whose box lies off the origin by at least twice that extent
// onto it. Both steps are exact: a power of two only changes exponents, and a subtraction of
// two numbers within a factor of two of each other is exact (Sterbenz). Every coordinate ends
// within [-3, 3]. Throws InputError when the points are not finite or all coincide.
CoordinateNormalisation normalise_coordinates(std::vector<Vec3>& points);

}  // namespace isocorr
