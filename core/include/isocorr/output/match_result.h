// What a match returns, in the order a user reads it: the output (maps and confidence),
// the final quality measures, the warnings and notes, the time of each stage, and the
// diagnostics of how the result was reached (level 0, tracking, refinement, part search),
// which the report and the benchmarks show.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "isocorr/matching/flip_tracking.h"
#include "isocorr/matching/level0_search.h"
#include "isocorr/output/match_output.h"
#include "isocorr/refinement/candidate_screening.h"
#include "isocorr/refinement/dense_choice.h"
#include "isocorr/util/stage_clock.h"

namespace isocorr {

// The final measures of the returned forward map.
struct MatchQuality {
  double diso = 0;         // C2F: D_iso of the dense forward map over the anchors; refined:
                           // distortion between coarse samples
  double diso_max = 0;     // d_iso-dagger
  double orientation = 0;  // fraction of source faces keeping handedness
  // share of neighbouring sample pairs the map tears (diagnosis/map_tearing.h); -1: not
  // measured (a part's map, whose scale the measure cannot take)
  double torn_share = -1;
  // method = part or ravac: the source's scale per target unit (in the files' units), and
  // the share of the target's area the part's image covers (reverse map -1 elsewhere).
  double part_scale = 0;
  double target_matched_share = 1;
};

// What a user should act on (the input was repaired, a pipeline fell back), apart from the
// remarks on routine steps, so that a log can tell the two apart.
struct MatchMessages {
  std::vector<std::string> warnings;
  std::vector<std::string> notes;
};

struct MatchTimings {
  std::vector<StageTiming> stages;        // in order; their sum is the match's time
  std::vector<StageTiming> refine_steps;  // refine = zoomout: the refine stage's steps, within its time
};

struct Level0Diagnostics {
  std::vector<Level0Map> maps;   // sorted by D_iso
  int tracked_by_jump_rule = 0;  // N before the min/max bounds
};

struct TrackingDiagnostics {
  std::vector<TrackedMap> maps;
  int chosen = 0;  // index into `maps`: the map the result comes from
};

// refine = zoomout: the screened tracked maps, the refined candidates, the winner among
// them and why it won.
struct RefinementDiagnostics {
  std::vector<ScreenEvidence> screened;
  std::vector<DenseCandidate> candidates;
  int chosen = 0;
  std::string why;
  // The winner's last functional map, k x k over the first k spectral basis functions of
  // each shape: source_basis * C ~ target_basis at the forward map's rows (the pull-back of
  // target functions). Empty when the refinement did not run.
  Eigen::MatrixXf functional_map;
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

struct PartDiagnostics {
  std::vector<PartCandidate> candidates;  // the part search's dense candidates, in tracked order
};

// What the landmarks (MatchSettings::landmarks, transfer/landmarks.h) did; all zero without.
struct LandmarkDiagnostics {
  int count = 0;             // distinct landmarks in the shapes' clean numbering
  int level0_dropped = 0;    // level-0 maps dropped for disagreeing with them
  bool level0_none_agreed = false;  // none agreed: the least disagreeing map was kept
  // The chosen map's distance from each landmark's image to its partner, / the target's
  // diameter, before the landmarks were pinned (the final map sends each to its partner).
  std::vector<double> chosen_errors;
  bool honoured = true;      // every one of chosen_errors is within kLandmarkTolerance
};

// Whether the result may be wrong (diagnosis/verdict.h): the evidence a right map shows,
// checked after the match. A suspect result deserves a look before it is used.
struct MatchVerdict {
  bool suspect = false;
  std::vector<std::string> reasons;  // one sentence per failed check, with its figure; empty when ok
  const char* status() const { return suspect ? "suspect" : "ok"; }
};

struct MatchDiagnostics {
  Level0Diagnostics level0;
  LandmarkDiagnostics landmarks;
  TrackingDiagnostics tracking;
  RefinementDiagnostics refinement;
  PartDiagnostics part;
};

// The figures of a finished match that a job listing shows (the API's MatchSummary).
struct MatchSummary {
  int source_vertices = 0, target_vertices = 0;
  double diso = 0, diso_max = 0, dense_orientation = 0;
  int level0_maps = 0, tracked_maps = 0, chosen_level0_rank = 0;
  std::vector<StageTiming> timings;
  std::vector<std::string> notes;  // warnings first
  std::string verdict;             // "ok" or "suspect"; "" for a result stored before verdicts
  std::vector<std::string> verdict_reasons;
};

struct MatchResult {
  MatchOutput output;  // maps, confidence and (from run_match) the report
  MatchQuality quality;
  MatchMessages messages;
  MatchTimings timings;
  MatchDiagnostics diagnostics;
  MatchVerdict verdict;

  MatchSummary summary() const;
};

}  // namespace isocorr
