// Landmarks: correspondences the user knows (MatchSettings::landmarks, in the files'
// numbering). An isometry cannot tell a body from itself turned or mirrored, and on a
// nearly symmetric pair the engine's evidence may not either; one landmark off the
// symmetry decides. The match uses them in three places:
//  - level 0 (level0_search.h, drop_level0_maps): a level-0 map whose samples lie at other
//    distances from the landmarks than their images do from the landmarks' partners is
//    dropped;
//  - the choice among refined candidates (dense_choice.h): a candidate that sends a landmark
//    farther than kLandmarkTolerance from its partner loses to one that does not;
//  - the refinement: the pairs join ZoomOut's starting pairs, and the final maps send each
//    landmark to its partner, both ways (pin_landmarks).
// With the part methods the complete pipeline uses them as above; the part search's map
// and the complete pipeline's then compete on them first (part_or_whole.cpp).
// This file holds the geometry they need: validation, the landmarks' geodesic fields, and
// the measures of agreement.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "isocorr/matching/dense_map.h"
#include "isocorr/output/match_result.h"
#include "isocorr/settings/match_settings.h"
#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

// A landmark sent farther than this (geodesic distance on the target, / its diameter) from
// its partner is not honoured: the evaluation counts a point that far off as misplaced (its
// flip rule without symmetry ground truth, docs/benchmarks.md). A turned or mirrored map
// sends a limb's landmark 0.3-0.9 away; a right map before its finishing can leave a limb
// tip 0.12 off in an extreme pose (SCAPE 004 -> 013, where 0.1 let only a partly flipped map
// through and lost the pair).
inline constexpr double kLandmarkTolerance = 0.2;

// Each landmark costs a geodesic field on each mesh (and their memory, 8 bytes a vertex):
// a few name a correspondence, a thousand would be a map.
inline constexpr size_t kMaxLandmarks = 100;

// What is wrong with one entry of a landmark list.
struct LandmarkProblem {
  size_t index = 0;     // the entry at fault (the later one of a duplicate or contradiction)
  std::string message;  // without the index: "source vertex 12 is given two targets, 40 and 41"
  std::optional<size_t> earlier;  // the entry it repeats or contradicts
};

// The first problem of `landmarks`: an entry beyond kMaxLandmarks, a negative index, an index not below the vertex count
// of its mesh (counts < 0: unknown, not checked), the same pair twice, or one vertex given
// two partners. Nothing when they are fine.
std::optional<LandmarkProblem> find_landmark_problem(const std::vector<Landmark>& landmarks,
                                                     int source_vertices = -1, int target_vertices = -1);

// Throws InputError "landmarks[i]: <problem> (landmarks[j])" for find_landmark_problem's
// first problem, j the earlier entry when there is one.
void validate_landmarks(const std::vector<Landmark>& landmarks, int source_vertices = -1, int target_vertices = -1);

// The landmarks of one pair of preprocessed shapes, in their clean numbering, with one
// geodesic field per landmark on each shape (divided by that shape's diameter). Empty when
// there are none: every measure below is then 0. The landmarks must be in range
// (validate_landmarks with the files' vertex counts); two that cleaning welded into one
// vertex count once.
class LandmarkGeometry {
 public:
  LandmarkGeometry() = default;
  LandmarkGeometry(const PreprocessedShape& source, const PreprocessedShape& target,
                   const std::vector<Landmark>& in_files);

  bool empty() const { return pairs_.empty(); }
  int size() const { return static_cast<int>(pairs_.size()); }
  // (source vertex, target vertex), clean numbering.
  const std::vector<std::pair<int, int>>& pairs() const { return pairs_; }

  // How far a map's pairs disagree with the landmarks: the mean over the pairs (a, b) and
  // the landmarks (s, t) of |g_S(a, s) - g_T(b, t)|. This is d_iso of each landmark pair
  // against the map's pairs as anchors (docs/algorithm.md): a map the landmarks agree with
  // scores about its own D_iso, a turned or mirrored one far more.
  double disagreement(const std::vector<std::pair<int, int>>& vertex_pairs) const;

  // The geodesic distance on the target from each landmark's image under `forward` (clean
  // source vertex -> clean target vertex) to its partner, / the target's diameter.
  std::vector<double> errors(const std::vector<int>& forward) const;
  // The largest of errors(forward); 0 without landmarks.
  double largest_error(const std::vector<int>& forward) const;

 private:
  std::vector<std::pair<int, int>> pairs_;
  std::vector<std::vector<float>> source_fields_, target_fields_;  // per landmark, #V, / diameter
};

// Sends each landmark's source vertex to its target vertex in `forward` and the target
// vertex back in `reverse` (clean numbering): the user's correspondences hold exactly.
void pin_landmarks(const LandmarkGeometry& landmarks, std::vector<int>& forward, std::vector<int>& reverse);

// The chosen map measured against the landmarks (result.diagnostics.landmarks, and a warning
// when one is beyond kLandmarkTolerance), then pinned. Nothing without landmarks.
void hold_landmarks(const LandmarkGeometry& landmarks, DenseMap& dense, MatchResult& result);

}  // namespace isocorr
