// Preprocessing options shared by the tests of spectral refinement: a basis and sample
// count small enough for the procedural meshes.
#pragma once

#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr::test_support {

inline PreprocessOptions spectral_options() {
  PreprocessOptions options;
  options.spectral_basis = 60;
  options.spectral_samples = 800;
  return options;
}

}  // namespace isocorr::test_support
