// Symmetric-flip tracking (paper Sec. 4): each of the N best level-0 maps is pursued on
// its own through levels 1..K1 of C2FCM, and scored there.
#pragma once

#include <vector>

#include "isocorr/matching/level0_search.h"
#include "isocorr/matching/orientation.h"
#include "isocorr/matching/sample_pair.h"
#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

struct TrackingOptions {
  int anchor_cap = 100;        // E: anchors used for d_iso (the coarsest pairs, evenly spread)
  double window_factor = 2.0;  // a new sample's image is sought within this many times its
                               // distance to its parent sample, around the parent's image
  double trim_fraction = 0.2;  // share of the largest d_iso terms ignored when matching a
                               // sample (robust to misplaced anchors and non-isometric parts)
  bool pool_all_levels = true;  // offer every target sample at every level
  bool handedness_guard = true;  // a new pair must keep the handedness of nearby pairs
};

struct TrackedMap {
  int level0_rank = 0;          // position in the sorted level-0 list
  double level0_diso = 0;
  std::vector<SamplePair> pairs;  // all pairs up to level K1, coarse first
  double diso = 0;              // D_iso of the pairs at level K1 (paper's selection value)
  double orientation = 0;       // fraction of sample triangles that keep their handedness
};

// What tracking needs of the source alone, the same for every level-0 map of a pair: the
// order in which source samples are matched (every map's pairs come in this order), the
// distances between them, and the source's half of the handedness tests (orientation.h).
// Built once per pair, so that each map's tracking does only the target's work.
struct TrackingPlan {
  struct Step {
    int source_sample = 0;
    std::vector<GuardCorners> guard;  // over the pairs before its level (empty without the guard)
  };
  int level0_count = 0;                   // source samples 0..M-1 are matched at level 0
  std::vector<std::vector<Step>> levels;  // levels 1..K1, each in matching order
  std::vector<PairTriangle> orientation;  // over all pairs, level-0 ones first
  int pair_count = 0;
  std::vector<float> pair_distances;  // pair_count squared
  // The distances from every pair's source sample to pair p's (sample_field), in pair order.
  const float* distances_to(size_t p) const { return pair_distances.data() + p * pair_count; }
};

// Levels 1..`levels` after `level0_count` level-0 samples; each new source sample (of steps
// <= 2k at level k) in index order.
TrackingPlan plan_tracking(const PreprocessedShape& source, int level0_count, int levels,
                           const TrackingOptions& options);

// Refines one level-0 map (source samples 0..M-1 to target samples `map.target_of`)
// level by level up to the plan's last level (the shapes' decision level K1). Each new
// source sample is matched to the target sample near its parent's image that minimises
// d_iso against the pairs of earlier levels: with many reliable anchors this per-sample
// choice avoids the drift of small combinatorial patches (docs/decisions.md, "Per-sample
// refinement rather than combinatorial patches").
TrackedMap track_map(const PreprocessedShape& source, const PreprocessedShape& target, const TrackingPlan& plan,
                     const Level0Map& map, int rank, const TrackingOptions& options, const JobControl& control);

// D_iso of a set of sample pairs: mean over pairs of d_iso against all the others, each
// pair at its vertex-accurate image where it has one.
double sample_map_diso(const PreprocessedShape& source, const PreprocessedShape& target,
                       const std::vector<SamplePair>& pairs);

}  // namespace isocorr
