// Part matching (Sahillioglu & Yemez, PG'12; docs/partial.md): the source is a
// part of the target's shape, such as a scan with a missing limb or half a body, at a
// scale that need not be the target's.
//
// 1. Extremities: the source's extremity samples away from its boundary (a cut makes
//    false extremities along its rim) are matched to the target's level-0 samples over all
//    injective maps, ranked by a scale-free distortion on raw geodesics (kappa, source
//    units per target unit, from each map's exact distances), since a part's geodesic
//    diameter says nothing about its scale; kappa below sqrt(part area / target area) is
//    impossible. When no map onto level 0 is consistent (the part has tips the target's
//    level 0 lacks), the target's first 20 samples are offered instead.
// 2. Screening: few extremities, or distances all lengthened by a cut, leave many maps
//    equally consistent, so every map also grows the first levels' samples; the candidates
//    are half the best by step 1 and half the best screened.
// 3. Each candidate's source samples are matched coarse to fine to target samples against
//    all pairs matched before (near the parent's image, handedness kept, at its kappa
//    re-estimated from trusted matches) and extended to every vertex; among the maps that
//    keep face handedness (symmetric flips do not), the one whose smoothed curvature agrees
//    best wins (dense_choice.h).
// 4. The winner's anchors move to vertex accuracy; every source vertex is matched by
//    descent of their weighted mismatch; a target vertex gets a source vertex only where
//    the part's image covers it (-1 elsewhere).
//
// Steps 1-2 live in part_extremity_search.cpp, 3 in part_growth.cpp, 4 in part_dense_map.cpp,
// the evidence in part_evidence.cpp, and the stages in order in part_matching.cpp.
//
// Boundary awareness: removing surface can only lengthen geodesics, and only those whose
// path could touch the cut: a source distance g(x, y) is the full shape's when
// g(x, y) < b(x) + b(y), b = distance to the boundary. Other distances are upper bounds:
// a target distance longer than them is penalised, a shorter one is not. So nothing is
// down-weighted by a guessed band: every term is either exact or one-sided.
#pragma once

#include "isocorr/matching/dense_map.h"
#include "isocorr/output/match_result.h"
#include "isocorr/settings/match_settings.h"
#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

// Fills `result` (level0, tracked, chosen, notes) and returns the dense map of clean
// vertices; dense.reverse holds -1 for target vertices outside the part's image.
DenseMap match_part(const PreprocessedShape& source, const PreprocessedShape& target, const MatchSettings& settings,
                    MatchResult& result, const JobControl& control);

// Evidence on which dense maps of a part compete, whatever made them: the part search
// above, or the complete-shape pipeline (a part that lost only holes or a hand is matched
// best as if it were whole; one that lost half its area is not).
struct PartMapEvidence {
  double orientation = 0;  // fraction of source faces whose image keeps handedness
  double distortion = 0;   // boundary-aware mean mismatch over sample pairs, / source diameter
  double scale = 1;        // kappa of the map: median source/target ratio of exact distances
  double curvature = 0;    // smoothed curvature disagreement at kappa, away from the rims (part_geometry.h)
};

// One evidence per forward map (clean numbering), in order; the part's boundary distances
// are computed once, its curvature once per map at the map's kappa (part_geometry.h).
// Costs kPartEvidenceSources fast-marching fields on the target per map.
std::vector<PartMapEvidence> measure_part_maps(const PreprocessedShape& source, const PreprocessedShape& target,
                                               const std::vector<const std::vector<int>*>& forwards, int threads);

// Whether part maps are finished (refined spectrally and polished) before they compete:
// with the refinement on and a rigidity polish to give.
inline bool finishes_part_maps(const MatchSettings& settings) {
  return settings.refine != RefineMethod::kNone && settings.rigidity.iterations > 0;
}

// A part's map made by the complete pipeline, whose ZoomOut fitted a square C as if the
// part were whole, refined as the part search's maps are: spectrally with a rectangular C
// (partial_refinement.h), then the rigidity polish at the map's kappa `scale`. Returns the
// map with its forward residuals (no reverse map).
DenseMap refine_as_part_map(const PreprocessedShape& source, const PreprocessedShape& target,
                            const MatchSettings& settings, double scale, const std::vector<int>& forward,
                            const JobControl& control);

// Fills dense.reverse (and reverse_diso) from dense.forward: target vertices near an image
// take the source vertex of the nearest one, the rest -1 (no counterpart).
void add_part_reverse_map(const PreprocessedShape& source, const PreprocessedShape& target, double scale,
                          DenseMap& dense);

// Share of the target's area whose vertices have a counterpart in `reverse` (not -1), from
// the target's vertex_areas (computed once by a caller that asks for several maps).
double matched_area_share(const std::vector<double>& target_vertex_areas, const std::vector<int>& reverse);

}  // namespace isocorr
