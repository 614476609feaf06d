// Every setting of one match, grouped by the stage that reads it. The fields are listed
// once more, with their ranges and help, in settings_schema.cpp: that table is what the
// CLI, the API codec, the job journal, the report and the cache key are derived from.
#pragma once

#include <vector>

#include "isocorr/matching/dense_map.h"
#include "isocorr/matching/flip_tracking.h"
#include "isocorr/refinement/rigidity_polish.h"
#include "isocorr/refinement/zoomout.h"
#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

enum class RefineMethod {
  kZoomOut,  // default: spectral refinement of the best tracked candidates, chosen by dense evidence
  kNone,     // the C2F dense level alone (anchor descriptors + descent): the paper's pipeline
};

enum class MatchMethod {
  kFull,  // default: both meshes are complete shapes (C2F with flip tracking)
  kPart,   // the source is a part of the target's shape, at any scale (partial/part_matching.h)
  kRavac,  // either mesh may be partial, at any scale: extremity maps by rank, vote, combine
};

enum class SelectionRule {
  kOrientationThenDistortion,  // default: keep the tracked maps that best keep orientation, then least D_iso
  kLeastDistortion,            // the paper's rule: least D_iso at level K1
};

// A correspondence the user knows (a nose, a left hand): source vertex -> target vertex, in
// the input files' numbering. transfer/landmarks.h says how the match uses them.
struct Landmark {
  int source_vertex = 0;
  int target_vertex = 0;
  bool operator==(const Landmark&) const = default;
};

struct MatchSettings {
  PreprocessOptions preprocess;     // per-mesh part (cached per mesh by the service)
  MatchMethod method = MatchMethod::kFull;
  // Part matching: source extremities matched combinatorially (paper: M = 5), and the best
  // extremity maps grown to sample maps, one of which is chosen (symmetric flips).
  int part_extremities = 5;
  // Half by extremity distortion, half by screening (part_extremity_search.cpp). Larger pools hold
  // right maps more often; once the part's curvature was compared at the whole's lengths
  // (part_geometry.h) the choice found them: 32 -> 64 took the benchmark's cuts from 23 to
  // 25 of 36 and the cuts of sets never used for a choice (faust_reg6890,
  // faust_remeshed_lps) from 18 to 23 of 24, for 5% more time on a FAUST 5k part.
  int part_candidates = 64;
  // M (paper: up to 8). 0 = automatic: the number of extremities of the source, within
  // [5, 7]. Samples beyond the extremities are poorly aligned between two meshes and
  // mislead tracking: on 12 SCAPE pairs M = 5 gave 75% flip-free against 58% for M = 7,
  // while quadrupeds (7+ extremities) do best with M = 7.
  int level0_samples = 0;
  int level0_extra_targets = 1;     // M' - M (paper: 1; the prototype found more useless)
  double max_level0_diso = 0.15;    // level-0 maps above this are not kept (paper: 0.15)
  int max_level0_maps = 300;        // at most this many sorted level-0 maps are kept
  // Bounds on N from the jump rule. The paper tracks exactly N, but tracking costs only
  // milliseconds per map (it works on samples, not vertices), and on TOSCA the right map
  // often sits far beyond N: tracking 16 / 48 / 96 maps gave 72% / 83% / 83% flip-free on
  // tosca_isometric_5k, and 64 -> 192 maps took tosca_hires from 13 to 14 of 18 pairs
  // (cat1 -> cat3's only right map ranks past 100). min_tracked = max_tracked = N
  // restores the paper's behaviour.
  int min_tracked = 192;
  int max_tracked = 192;
  SelectionRule selection = SelectionRule::kOrientationThenDistortion;
  double orientation_threshold = 0.5;  // below this, no tracked map counts as orientation-preserving
  double orientation_margin = 0.1;     // maps this close to the best orientation compete on D_iso
  double orientation_weight = 0.025;   // ... on D_iso - weight * orientation agreement
  TrackingOptions tracking;
  DenseOptions dense;               // the C2F dense level (refine = none)
  RefineMethod refine = RefineMethod::kZoomOut;
  // The best ranked distinct tracked maps screened by a short refinement on the samples up
  // to basis size screen_k_end (candidate_screening.h); refine_candidates of them, taken in
  // turn from the ranking and from the screen (least curvature disagreement first), are
  // refined fully, and up to three of those are finished and compared (refinement.h). On
  // SCAPE's extreme poses the right tracked map ranked anywhere up to 20th; 32 screened
  // starts gave a right candidate on 8 of the 9 pairs that had none among the 4 best
  // ranked (16: 5 of 9), for about 0.03 s a start at 5K vertices.
  int screen_candidates = 32;
  int screen_k_end = 70;
  int refine_candidates = 4;
  ZoomOutOptions zoomout;
  bool outlier_repair = true;       // each refined map's misplaced regions searched again (outlier_repair.h)
  RigidityOptions rigidity;         // each refined map's last stage (rigidity_polish.h)
  // More rigidity iterations per fit weight for the chosen map alone, kept only where its
  // curvature then agrees better (final_polish.h); 0 = none. Off by default: at 130, 8%
  // less error on SCAPE's first 10 pairs and 1-2% on TOSCA 5k and FAUST 5k, for 0.5 s more
  // on a 5K pair and 2 s on a 12.5K one.
  int rigidity_final_iterations = 0;
  // Refinements of the chosen map from itself (refine_again in refinement.h); 0 = none. Off
  // by default: one pass takes SCAPE's first 10 pairs from D_grd 0.0091 to 0.0082 (two:
  // 0.0079) for 0.6 s more per pair, but leaves TOSCA 5k and FAUST 5k as they were.
  int refine_passes = 0;
  int dense_choice_sources = 16;    // fast-marching fields per candidate for its dense distortion
  int threads = 0;                  // 0 = all cores; results do not depend on it
  // Known correspondences: a list, so not a row of the settings table (settings_schema.cpp
  // says how it is handled beside it). Per match: not part of the shape cache key.
  std::vector<Landmark> landmarks;

  // Throws InputError naming the first setting out of range (the schema's ranges), the
  // first pair of settings that contradict each other, or the first bad landmark
  // ("landmarks[2]: ..."; their range against the meshes is checked once those are known).
  void validate() const;
};

}  // namespace isocorr
