// RAVAC, part matching in the most general setting (Sahillioglu & Yemez, CGF'14,
// rank-and-vote-and-combine; docs/partial.md): either shape may be partial or
// carry parts the other lacks, and the scale is unknown. Its output is a set of sparse
// extremity maps that part_matching.cpp grows to sample maps, extends to every vertex and
// chooses among, as it does for the part search's candidates.
//
// 1. Rank: every pair (source extremity, target extremity), both away from their shape's
//    boundary, gets the paper's d~_iso: the mean over map sizes k = 3..5 of the least
//    distortion of the pair against k - 1 other pairs, at the scale that suits it best
//    (with an unknown scale a single other pair always agrees, so k = 2 says nothing).
//    Each extremity's few best partners are qualified.
// 2. Vote: every triplet of qualified pairs whose three distance ratios agree (the scale
//    kappa is their mean) matches the evenly spread samples of its region of interest
//    and each of its pairs earns exp(-d / sigma), d its distortion against those matches.
// 3. Combine: a maximum-vote bipartite matching of the extremities, repeated with the
//    least confident match's two extremities removed until 3 are left; every such map is a
//    candidate, and so are the best-voted triplets (a map and its mirror collect the same
//    votes on a symmetric shape: the dense stage tells them apart by handedness).
#pragma once

#include <string>
#include <vector>

#include "isocorr/util/progress.h"
#include "part_geometry.h"

namespace isocorr {

// At most `wanted` distinct extremity maps, each with its kappa; notes get one line on
// what was ranked, voted and combined. Throws InputError when no triplet is consistent.
std::vector<ExtremityMap> ravac_extremity_maps(const PartGeometry& geometry, int wanted, int threads,
                                               std::vector<std::string>& notes, const JobControl& control);

}  // namespace isocorr
