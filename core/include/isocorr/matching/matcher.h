// Matching two preprocessed shapes: level-0 search -> flip tracking -> choice -> dense map.
// pipeline.h wraps it with the preprocessing; most callers want that.
#pragma once

#include <string>
#include <vector>

#include "isocorr/matching/dense_map.h"
#include "isocorr/matching/flip_tracking.h"
#include "isocorr/matching/level0_search.h"
#include "isocorr/output/match_output.h"
#include "isocorr/refinement/candidate_screening.h"
#include "isocorr/refinement/dense_choice.h"
#include "isocorr/settings/match_settings.h"
#include "isocorr/shape/preprocessed_shape.h"
#include "isocorr/util/stage_clock.h"

namespace isocorr {

// The figures of a finished match that a job listing shows (the API's MatchSummary).
struct MatchSummary {
  int source_vertices = 0, target_vertices = 0;
  double diso = 0, diso_max = 0, dense_orientation = 0;
  int level0_maps = 0, tracked_maps = 0, chosen_level0_rank = 0;
  std::vector<StageTiming> timings;
  std::vector<std::string> notes;
};

// method = part or ravac: one dense candidate of the part search (or RAVAC) and the
// evidence it was judged by (part_matching.h).
struct PartCandidate {
  double orientation = 0;    // share of faces keeping handedness
  double curvature = 0;      // PartCurvature disagreement at its kappa
  double covered = 0;        // its image's area / the area the part should cover (NaN: not measured, a non-finalist)
  double scale = 1;          // kappa
  double distortion = 0;     // its grown sample map's boundary-aware distortion
  double level0_distortion = 0;  // its extremity map's scale-invariant distortion
  bool finalist = false;     // polished and measured again; only finalists compete
  bool kept = false;         // the match's map is this candidate's, finished
  std::vector<int> forward;  // before vertex-accurate anchors (a finalist's polished; the files' numbering)
};

struct MatchResult {
  MatchOutput output;                     // maps, confidence and (from run_match) the report

  std::vector<Level0Map> level0;          // sorted by D_iso
  int tracked_by_jump_rule = 0;           // N before the min/max bounds
  std::vector<TrackedMap> tracked;
  int chosen = 0;                         // index into `tracked`: the map the result comes from
  std::vector<ScreenEvidence> screened;  // refine = zoomout: the screened tracked maps,
  std::vector<DenseCandidate> refined;    // the refined candidates,
  int refined_chosen = 0;                 // the winner among them,
  std::string refined_why;                // and why it won
  double diso = 0;                        // C2F: D_iso of the dense forward map over the anchors;
                                          // refined: distortion between coarse samples
  double diso_max = 0;                    // d_iso-dagger
  double dense_orientation = 0;           // fraction of source faces keeping handedness
  std::vector<StageTiming> timings;
  std::vector<StageTiming> refine_timings;  // refine = zoomout: the refine stage's steps
  // What a user should act on (the input was repaired, a pipeline fell back), apart from
  // the remarks on routine steps, so that a log can tell the two apart.
  std::vector<std::string> warnings;
  std::vector<std::string> notes;         // remarks on the steps taken, for the report
  // method = part: the source's scale per target unit, and the share of the target's area
  // the part's image covers (reverse map -1 elsewhere).
  double part_scale = 0;
  double target_matched_share = 1;
  std::vector<PartCandidate> part_candidates;  // the part search's dense candidates, in tracked order

  MatchSummary summary() const;
};

// Normalised geodesic distances between the first `count` samples of a shape, symmetrised
// (fast marching is not exactly symmetric): the level-0 search's input.
Eigen::MatrixXd sample_distances(const PreprocessedShape& shape, int count);
// The same between the listed samples, in their order.
Eigen::MatrixXd sample_distances(const PreprocessedShape& shape, const std::vector<int>& samples);

// The choice among tracked maps: those whose orientation agreement is within
// settings.orientation_margin of the best compete on D_iso - weight * orientation; returns
// all indices, best first.
std::vector<int> rank_tracked(const std::vector<TrackedMap>& tracked, const MatchSettings& settings);

// Matches two preprocessed shapes. `settings` must have passed validate() (run_match
// does that once). Deterministic for given inputs and settings. Reports progress as
// fractions of the match alone.
MatchResult match_shapes(const PreprocessedShape& source, const PreprocessedShape& target,
                         const MatchSettings& settings, const JobControl& control = {});

}  // namespace isocorr
