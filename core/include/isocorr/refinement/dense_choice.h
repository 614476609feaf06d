// Choosing among refined dense maps by evidence a mirror or a turned body cannot fake.
// Sparse evidence cannot: a human map that swaps left/right AND front/back is a 180-degree
// turn, keeps handedness and comes within a few per cent of the true map's sample D_iso
// (the prototype, faust_5k 000->001; docs/decisions.md). A mirror reverses the handedness
// of most faces; a turned map keeps it (face by face and neighbourhood by neighbourhood), and its geodesic
// distortion between coarse samples is often as low as the true map's (lower on 10 of 40
// faust_5k pairs), but it sends toes to heels and faces to the backs of heads. The heat
// kernel signature, truncated to the refinement's basis, barely sees that (right and
// turned SCAPE maps within 3%); the smoothed mean curvature (mean_curvature.h) does (the
// turned map's disagreement 20-30% higher). Measured over the refined candidates of all
// scape, faust_5k and tosca_isometric_5k pairs: choosing by least curvature disagreement
// picks a right map on every SCAPE pair that has one among its candidates (94/105, against
// 86/105 by heat signatures), and as often on FAUST.
// Curvature cannot see a swapped limb (a map that sends the left leg to the right one looks
// at the same shapes), and once more starts were screened such maps won on it by under 2%
// (SCAPE 002 -> 007, 002 -> 008, 004 -> 011). Their seams tear geodesics: their distortion
// is 12-97% above the right map's. So distortion enters the score, but weakly: a right map
// with a few misplaced regions or a stretched pose can be 20-30% more distorted than a turned
// body (SCAPE 003 -> 004, 005, 014, where the turned body's curvature is 11-22% higher), so
// curvature, the evidence a turned body cannot fake, must outweigh distortion per cent for
// per cent. The score is curvature disagreement times the cube root of distortion: a swapped
// limb loses when its distortion excess is more than 3 times its curvature advantage, in per
// cent (002 -> 007: 17% against 5%); a turned body wins only when its distortion is lower by
// more than 3 times its curvature excess. Over the refined candidates of every pair (choice replayed offline):
// SCAPE 100 -> 103 of 105 flip-free, faust_reg6890 109 -> 110 of 110 (007 -> 018), FAUST 5k
// and both TOSCA sets as before. Every exponent from 0.1 to 0.4 gives SCAPE 102-103 (0.25-0.3
// lose 002 -> 007) and faust_reg6890 110; 0.5-1 give 100-101 (the plain product lost
// 003 -> 004, 005, 014); 0 (curvature alone) loses two FAUST 5k and three faust_reg6890 pairs.
#pragma once

#include <string>
#include <vector>

#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

struct DenseEvidence {
  double orientation = 0;  // fraction of source faces whose image keeps handedness
  double neighbourhood_orientation = 0;  // the same over neighbourhoods (orientation.h)
  double signature_disagreement = 0;  // heat_signature_disagreement below
  double curvature_disagreement = 0;  // curvature_disagreement below
  double distortion = 0;   // mean |d_S(a, b) - d_T(F(a), F(b))| over coarse sample pairs, / diameter
  double distortion_max = 0;  // the largest mean over one sample a
  double round_trip = 0;   // mean geodesic distance from a sample to R(F(sample)), / diameter
};

// `forward` (source -> target) and `reverse` (target -> source) in clean-mesh numbering.
// Costs `distortion_sources` fast-marching fields on the target.
DenseEvidence measure_dense_map(const PreprocessedShape& source, const PreprocessedShape& target,
                                const std::vector<int>& forward, const std::vector<int>& reverse,
                                int distortion_sources, int threads);

// Mean over the source's spectral samples and 16 log-spaced times (from 4 ln 10 / the
// largest to 4 ln 10 / the first non-zero eigenvalue) of |h_S - h_T| / (h_S + h_T), h the
// heat kernel signature from the area-normalised basis, each time divided by its trace.
// 0 for a map between identical shapes; larger where the map moves points to places that
// look different at some scale.
double heat_signature_disagreement(const PreprocessedShape& source, const PreprocessedShape& target,
                                   const std::vector<int>& forward);

// The shapes' smoothed curvature disagreement (mean_curvature.h) along `forward` over the
// source's spectral samples (evenly spread: an area average).
double curvature_disagreement(const PreprocessedShape& source, const PreprocessedShape& target,
                              const std::vector<int>& forward);

struct DenseCandidate {
  int tracked_index = 0;  // which tracked map it was refined from
  DenseEvidence evidence;
  double score = 0;       // choice_score(evidence) (lower wins)
  // choice_score of its reverse map measured from the target, when a near tie was decided
  // by both directions (refinement.h); 0 when not measured.
  double reverse_score = 0;
  bool mirrored = false;  // orientation below mirror_threshold: not eligible
  // The largest distance from a landmark's image to its partner (transfer/landmarks.h), 0
  // without landmarks; above kLandmarkTolerance the candidate loses to any within it.
  double landmark_error = 0;
  bool finished = true;   // repaired and polished before the choice (refinement.h): an
                          // unfinished candidate competes only when no finished one is eligible
  std::vector<int> forward;  // its dense map (clean numbering; the files' in a MatchResult)
};

// A mirror image reverses the handedness of most faces; any map that keeps most is not one.
// A margin below the best map's orientation is no test: a right map with a few misplaced
// regions kept 0.61-0.78 where a turned body kept 0.82-0.91 (faust_reg6890 016 -> 019, SCAPE
// 004 -> 013), and curvature tells those two apart.
inline constexpr double kMirrorOrientation = 0.5;

// curvature_disagreement x cbrt(distortion): what the choice minimises (see the top).
double choice_score(const DenseEvidence& evidence);

// The orientation below which a dense candidate counts as mirrored: kMirrorOrientation, or
// `orientation_margin` below the best when even the best keeps less (inconsistently
// oriented meshes: then only the relative test is left).
double mirror_threshold(double best_orientation, double orientation_margin);

// Marks candidates below mirror_threshold as mirrored, scores the rest by choice_score,
// and returns the index of the winner: the least score among the eligible
// finished candidates, or among all eligible ones when no finished one is. When some
// candidate honours the landmarks (landmark_error within kLandmarkTolerance), only those
// that do compete, and the mirror test is made among them: the user's correspondence
// outranks every measure of the maps.
// `why` receives one sentence for the report.
int choose_dense_candidate(std::vector<DenseCandidate>& candidates, double orientation_margin, std::string& why);

}  // namespace isocorr
