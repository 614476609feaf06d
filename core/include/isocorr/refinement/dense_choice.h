// Choosing among refined dense maps by evidence a mirror or a turned body cannot fake.
// Sparse evidence cannot: a human map that swaps left/right AND front/back is a 180-degree
// turn, keeps handedness and comes within a few per cent of the true map's sample D_iso
// (ALGORITHM.md, faust_5k 000->001). On a dense map both show: a mirror reverses the
// handedness of most faces, and a turned map stretches geodesics between distant points
// and does not come back to where it started through the reverse map.
#pragma once

#include <string>
#include <vector>

#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

struct DenseEvidence {
  double orientation = 0;  // fraction of source faces whose image keeps handedness
  double distortion = 0;   // mean |d_S(a, b) - d_T(F(a), F(b))| over coarse sample pairs, / diameter
  double distortion_max = 0;  // the largest mean over one sample a
  double round_trip = 0;   // mean geodesic distance from a sample to R(F(sample)), / diameter
};

// `forward` (source -> target) and `reverse` (target -> source) in clean-mesh numbering.
// Costs `distortion_sources` fast-marching fields on the target.
DenseEvidence measure_dense_map(const PreprocessedShape& source, const PreprocessedShape& target,
                                const std::vector<int>& forward, const std::vector<int>& reverse,
                                int distortion_sources, int threads);

struct DenseCandidate {
  int tracked_index = 0;  // which tracked map it was refined from
  DenseEvidence evidence;
  double score = 0;       // distortion + round_trip (lower wins)
  bool mirrored = false;  // orientation too far below the best: not eligible
};

// Marks candidates whose orientation lies more than `orientation_margin` below the best as
// mirrored, scores the rest, and returns the index of the winner (least score among the
// eligible). `why` receives one sentence for the report.
int choose_dense_candidate(std::vector<DenseCandidate>& candidates, double orientation_margin, std::string& why);

}  // namespace isocorr
