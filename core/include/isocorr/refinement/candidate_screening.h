// Which tracked maps are worth a full refinement.
//
// The sparse ranking of tracked maps (D_iso and orientation at the decision level) cannot
// tell a right map from a 180-degree turned body on extreme poses: on SCAPE's nine pairs
// without a right candidate among the 4 best ranked, the right tracked maps ranked 4th to
// 20th. A short spectral refinement on the samples alone (ZoomOut up to a small basis, no
// dense recovery) turns each start into a smooth map cheaply, and the smoothed curvature
// then separates them: over the 16 best ranked distinct tracked maps of those nine pairs
// (2000 samples), the least curvature disagreement at basis size 70 was a right map on 6
// of the 7 pairs that had one (at 40: 4 of 7). So many starts are screened this way, and
// only a few go on to a full refinement; their sampled iterations continue from where the
// screen stopped, so the screen costs nothing for them.
#pragma once

#include <vector>

#include "isocorr/matching/flip_tracking.h"
#include "isocorr/refinement/zoomout.h"
#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

// The screen runs on the first this many spectral samples of each shape (half the default
// 2000): the all-pairs nearest-row search costs the product of the two counts. At 500 the
// screen missed the right start on 2 more of SCAPE's 9 hardest pairs.
inline constexpr size_t kScreenSamples = 1000;

// What the screen measured of one start (also reported).
struct ScreenEvidence {
  int tracked_index = 0;   // the tracked map it started from
  double orientation = 0;  // handedness kept by the sampled map (spread_sample_map below)
  double curvature = 0;    // curvature disagreement at the screen's samples (mean_curvature.h)
};

struct ScreenedStart {
  ScreenEvidence evidence;
  SampleMap sampled;  // its sampled map at the screen's basis size, on kScreenSamples samples
};

// Refines each of `starts` (tracked-map indices) on the samples up to basis size `k_end`
// and measures it. `fixed_pairs` (source vertex, target vertex: the landmarks) join every
// start's pairs. In the order of `starts`; deterministic.
std::vector<ScreenedStart> screen_tracked_maps(const PreprocessedShape& source, const PreprocessedShape& target,
                                               const std::vector<TrackedMap>& tracked, const std::vector<int>& starts,
                                               int k_end, const ZoomOutOptions& options,
                                               const JobControl& control = {},
                                               const std::vector<std::pair<int, int>>& fixed_pairs = {});

// The `count` starts worth a full refinement, taken in turn from two orders: the tracked
// ranking (the order of `screened`), skipping starts the screen found mirrored, and the
// screen's (those that pass the dense choice's mirror test first, then the least
// curvature disagreement). Both are needed: the screen alone found right maps the ranking
// had missed on SCAPE's extreme poses, but dropped the ranking's right map for a map with a
// swapped limb on 2 of the first 15 SCAPE pairs. A start whose sampled map is the same as
// an earlier pick's (same_images) is skipped: distinct starts often converge to one map.
std::vector<ScreenedStart> starts_to_refine(std::vector<ScreenedStart> screened, int count, double orientation_margin,
                                            const MeshTopology& target_topology);

// Two maps of the same points are one map when at least 80% of the points have the same
// image or neighbouring ones.
bool same_images(const std::vector<int>& a, const std::vector<int>& b, const MeshTopology& target_topology);

// A dense map from a sampled one (`sample_images[i]` the image of sample i): each vertex
// goes where its nearest sample goes (`nearest_sample`, from nearest_centre in
// vertex_spreading.h, the same for every map of the same samples). Its faces that span
// three samples' images are the sample map's triangles, enough to read the handedness a
// map keeps.
std::vector<int> spread_sample_map(const std::vector<int>& nearest_sample, const std::vector<int>& sample_images);

// The SpectralSide of a preprocessed shape: its basis, topology, spectral samples and eigenvalues.
SpectralSide spectral_side(const PreprocessedShape& shape);

}  // namespace isocorr
