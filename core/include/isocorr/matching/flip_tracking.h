// Symmetric-flip tracking (paper Sec. 4): each of the N best level-0 maps is pursued on
// its own through levels 1..K1 of C2FCM, and scored there.
#pragma once

#include <vector>

#include "isocorr/matching/level0_search.h"
#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

// A correspondence between sample i of the source and sample j of the target hierarchy.
struct SamplePair {
  int source_sample = 0;
  int target_sample = 0;
  float diso = 0;  // d_iso of the pair against the anchors it was matched with
  int target_vertex = -1;  // the target vertex (not sample) that best agrees with the anchors
};

// The target vertex a pair maps to: its vertex-accurate image once refined, else its sample.
inline int image_vertex(const PreprocessedShape& target, const SamplePair& pair) {
  return pair.target_vertex >= 0 ? pair.target_vertex : target.sample_vertex(pair.target_sample);
}

struct TrackingOptions {
  int anchor_cap = 100;        // E: anchors used for d_iso (the coarsest pairs, evenly spread)
  double window_factor = 2.0;  // a new sample's image is sought within this many times its
                               // distance to its parent sample, around the parent's image
  double trim_fraction = 0.2;  // share of the largest d_iso terms ignored when matching a
                               // sample (robust to misplaced anchors and non-isometric parts)
  bool pool_all_levels = true;  // offer every target sample at every level
  bool handedness_guard = true;  // a new pair must keep the handedness of nearby pairs
  int threads = 0;
};

struct TrackedMap {
  int level0_rank = 0;          // position in the sorted level-0 list
  double level0_diso = 0;
  std::vector<SamplePair> pairs;  // all pairs up to level K1, coarse first
  double diso = 0;              // D_iso of the pairs at level K1 (paper's selection value)
  double orientation = 0;       // fraction of sample triangles that keep their handedness
};

// Refines one level-0 map (source samples 0..M-1 to target samples `map.target_of`)
// level by level up to the shapes' decision level K1. Each new source sample (of steps
// <= 2k at level k) is matched to the target sample (of steps <= 2k+1) near its parent's
// image that minimises d_iso against the pairs of earlier levels: with many reliable
// anchors this per-sample choice avoids the drift of small combinatorial patches
// (ALGORITHM.md, "What a prototype measured").
TrackedMap track_map(const PreprocessedShape& source, const PreprocessedShape& target,
                     const Level0Map& map, int rank, const TrackingOptions& options,
                     const JobControl& control);

// D_iso of a set of sample pairs: mean over pairs of d_iso against all the others, each
// pair at its vertex-accurate image where it has one.
double sample_map_diso(const PreprocessedShape& source, const PreprocessedShape& target,
                       const std::vector<SamplePair>& pairs);

}  // namespace isocorr
