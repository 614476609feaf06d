// The preprocessed shape's derived tables agree with the fields they are read from.
#include "isocorr/shape/preprocessed_shape.h"

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"

namespace isocorr {
namespace {

TEST(PreprocessedShape, SampleFieldIsTheFieldAtEachSample) {
  const auto shape = PreprocessedShape::build(limbed_blob(4), PreprocessOptions{});
  ASSERT_GT(shape->num_samples(), 20);
  for (int i = 0; i < shape->num_samples(); ++i) {
    EXPECT_EQ(shape->sample_field(i, i), 0.f);
    for (int j = 0; j < shape->num_samples(); ++j)
      ASSERT_EQ(shape->sample_field(i, j), shape->field(i, shape->sample_vertex(j))) << i << ", " << j;
  }
  // Geodesic distances: the table is nearly symmetric and within the normalised diameter.
  const int last = shape->num_samples() - 1;
  EXPECT_NEAR(shape->sample_field(0, last), shape->sample_field(last, 0), 0.02);
  EXPECT_GT(shape->sample_field(0, last), 0.f);
  EXPECT_LE(shape->sample_field(0, last), 1.f);
}

}  // namespace
}  // namespace isocorr
