// Spectral refinement of a part's map to a whole (ZoomOut with a rectangular functional
// map, after the partial functional maps of Rodola et al. 2017): the part's eigenfunctions
// are its own, with a free (Neumann) rim, and by Weyl's law its i-th eigenvalue is about
// the whole's (i / r)-th, r the share of the whole's area the part covers. So C is fitted
// between the first r*k functions of the part and the first k of the whole, k grown as in
// the complete pipeline, and each part vertex goes to the whole's vertex nearest in the
// whole's embedding. The part search's maps come from geodesic anchors a sample spacing
// apart; this takes out their slide the way ZoomOut does for complete shapes.
#pragma once

#include <vector>

#include "isocorr/refinement/zoomout.h"
#include "isocorr/shape/preprocessed_shape.h"
#include "isocorr/util/progress.h"

namespace isocorr {

// `forward` (every part vertex -> a whole vertex, clean numbering) refined; scale is the
// map's kappa (part length per whole length). `options` are the complete pipeline's ZoomOut
// options (k_start, k_end, k_step, dense_iterations); its commutativity term is not used.
// `forward` itself when either shape has no spectral basis.
std::vector<int> refine_part_map_spectrally(const PreprocessedShape& part, const PreprocessedShape& whole,
                                            double scale, const ZoomOutOptions& options,
                                            const std::vector<int>& forward, const JobControl& control = {});

}  // namespace isocorr
