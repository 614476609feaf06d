// Where a map tears the surface. A map that is right except in a region (a swapped limb, a
// patch sent to the other side) is continuous inside the region and outside it, but at the
// region's border neighbouring points land far apart. Over a whole shape a right map
// stretches no short distance several-fold; a turned or mirrored body keeps its
// neighbourhoods too (the near-tie and handedness checks see those), so tearing is the
// evidence of a regional error.
#pragma once

#include <vector>

#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

// A short distance stretched more than this many times is torn.
inline constexpr double kTearStretch = 2.5;
// Each sample is compared with this many nearest samples.
inline constexpr int kTearNeighbours = 6;
// A map with a larger share of torn pairs is suspect (diagnosis/verdict.h): above every
// right map of the development sets (at most 1.4%); docs/decisions.md has the measurement.
inline constexpr double kTornShare = 0.015;

struct MapTearing {
  int pairs = 0;       // neighbouring sample pairs compared
  int torn_pairs = 0;  // ... whose images lie more than kTearStretch times as far apart
  int torn_samples = 0;  // samples with at least one torn pair
  double torn_share() const { return pairs > 0 ? static_cast<double>(torn_pairs) / pairs : 0.0; }
};

// A lower bound of the geodesic distance between vertices x and y of `shape`, / its
// diameter: the largest difference of its sample fields at the two (each is 1-Lipschitz).
float sample_field_distance_bound(const PreprocessedShape& shape, int x, int y);

// Compares each source sample with its kTearNeighbours nearest samples: a pair is torn when
// the geodesic distance between the images, / the target's diameter, exceeds kTearStretch
// times theirs, / the source's diameter. The images' distance is bounded below by the
// target's sample fields (the largest difference of a field at the two images: each field
// is 1-Lipschitz), so a pair counted torn is torn. `forward`: clean source vertex -> clean
// target vertex, every vertex mapped (a whole shape's map).
MapTearing measure_map_tearing(const PreprocessedShape& source, const PreprocessedShape& target,
                               const std::vector<int>& forward);

}  // namespace isocorr
