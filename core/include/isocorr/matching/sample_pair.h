// A matched pair of samples, the unit that tracking, the orientation tests and the part
// search pass around.
#pragma once

#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

// A correspondence between sample i of the source and sample j of the target hierarchy.
struct SamplePair {
  int source_sample = 0;
  int target_sample = 0;
  float diso = 0;  // d_iso of the pair against the anchors it was matched with
  int target_vertex = -1;  // the target vertex (not sample) that best agrees with the anchors
};

// The target vertex a pair maps to: its vertex-accurate image once refined, else its sample.
inline int image_vertex(const PreprocessedShape& target, const SamplePair& pair) {
  return pair.target_vertex >= 0 ? pair.target_vertex : target.sample_vertex(pair.target_sample);
}

}  // namespace isocorr
