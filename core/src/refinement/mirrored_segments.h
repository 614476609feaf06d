// Segments of a limb that a map sends mirrored, placed again before the rigidity polish.
//
// A spectral map can reverse a stretch of a nearly round limb while the rest of the body
// is right: around a limb the basis functions come in pairs of nearly equal eigenvalue,
// and the functional map's block for such a pair can converge to a reflection as easily as
// to a rotation. Measured on 15 SCAPE pairs (every 7th of pairs.tsv): the regions whose
// orientation the finished map reverses hold 20-50% of each pair's error (shins, forearms,
// hands), and the rigidity polish cannot undo them: the fold is a local minimum of its
// energy. Such a region's images lie on the right part of the target, in the wrong
// arrangement.
//
// Where the surroundings hold the region at two or more separate ends (a shin between the
// knee and the ankle), their rotations fix where it belongs: the region is placed again as
// the as-rigid-as-possible continuation of its surroundings and its vertices take the target
// vertices nearest their new positions, for the polish to start from. A region held at one
// end only (a hand, a paw) is left alone: a joint inside it can turn the rest anywhere (TOSCA
// cats' hind legs, continued from the hip, came out farther from the truth).
#pragma once

#include <vector>

#include "isocorr/shape/preprocessed_shape.h"
#include "rigidity_rings.h"

namespace isocorr {

struct MirroredSegments {
  int reversed_vertices = 0;  // vertices whose ring the map reverses (noise included)
  int segments = 0;           // regions placed again
};

// `image` (source vertex -> target vertex) and `deformed` (the source's positions, its
// images' positions to begin with) are changed inside the segments only; `rings` are the
// source's, scaled to the target. Deterministic.
MirroredSegments unfold_mirrored_segments(const PreprocessedShape& source, const PreprocessedShape& target,
                                          const Rings& rings, std::vector<int>& image, DeformedPoints& deformed);

}  // namespace isocorr
