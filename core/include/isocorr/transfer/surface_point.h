// A point on a triangle mesh, the unit of a precise map (precise_map.h). A header of its
// own so that the result type can hold precise maps without the mesh headers.
#pragma once

#include <array>
#include <vector>

namespace isocorr {

// Face `face` (an index into the mesh's faces, as read) and the weights of its three
// corners in the face's order (non-negative, summing to 1). face = -1: no point (a vertex
// that the map leaves unmatched).
struct SurfacePoint {
  int face = -1;
  std::array<float, 3> weights{1, 0, 0};
};

using PreciseMap = std::vector<SurfacePoint>;

}  // namespace isocorr
