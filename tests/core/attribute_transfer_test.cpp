// Attributes pulled through vertex and precise maps: copies, interpolation, label majority.
#include "isocorr/transfer/attribute_transfer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

// Two triangles over four vertices.
TriangleMesh square() {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.faces = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

const VertexTable kTwoColumns = {4, 2, {0, 10, 1, 11, 2, 12, 3, 13}};

TEST(AttributeTransfer, AVertexMapCopiesTheImageRows) {
  const VertexTable pulled = pull_values(kTwoColumns, {2, -1, 0});
  ASSERT_EQ(pulled.rows, 3);
  EXPECT_EQ(pulled.values[0], 2);
  EXPECT_EQ(pulled.values[1], 12);
  EXPECT_TRUE(std::isnan(pulled.values[2]) && std::isnan(pulled.values[3]));
  EXPECT_EQ(pulled.values[5], 10);
  EXPECT_THROW(pull_values(kTwoColumns, {4}), InputError);
}

TEST(AttributeTransfer, APreciseMapInterpolatesAtThePoint) {
  const PreciseMap map = {{0, {0.5f, 0.25f, 0.25f}}, {1, {0, 0, 1}}};
  const VertexTable pulled = pull_values(square(), kTwoColumns, map);
  EXPECT_NEAR(pulled.values[0], 0.5 * 0 + 0.25 * 1 + 0.25 * 2, 1e-6);
  EXPECT_NEAR(pulled.values[1], 0.5 * 10 + 0.25 * 11 + 0.25 * 12, 1e-6);
  EXPECT_NEAR(pulled.values[2], 3, 1e-6);
  EXPECT_THROW(pull_values(square(), {3, 1, {0, 1, 2}}, map), InputError);  // rows != vertices
}

TEST(AttributeTransfer, LabelsGoToTheMajorityNeverABlend) {
  const std::vector<int64_t> labels = {7, 9, 9, 7};
  // Corner 0 alone holds 0.4; corners 1 and 2 (both label 9) hold 0.6 together.
  const PreciseMap map = {{0, {0.4f, 0.3f, 0.3f}}, {1, {0.8f, 0.1f, 0.1f}}, {-1, {1, 0, 0}}};
  EXPECT_EQ(pull_labels(square(), labels, map), (std::vector<int64_t>{9, 7, kUnmatchedLabel}));
  EXPECT_EQ(pull_labels(labels, {1, 3, -1}), (std::vector<int64_t>{9, 7, kUnmatchedLabel}));
}

}  // namespace
}  // namespace isocorr
