// Colours through a map: the target's vertex takes the colour of its image on the source.
#include "isocorr/output/colour_transfer.h"

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"

namespace isocorr {
namespace {

TEST(ColourTransfer, PositionColoursSpanTheBoundingBox) {
  const TriangleMesh mesh = grid(3, 3);
  const std::vector<Rgb> colours = position_colours(mesh);
  ASSERT_EQ(colours.size(), 9u);
  EXPECT_EQ(colours[0][0], 30);   // lowest x
  EXPECT_EQ(colours[2][0], 255);  // highest x
}

TEST(ColourTransfer, ColoursFollowTheMap) {
  const std::vector<Rgb> colours = {Rgb{1, 2, 3}, Rgb{4, 5, 6}};
  const std::vector<Rgb> pulled = colours_through_map({1, 0, 7}, colours);
  ASSERT_EQ(pulled.size(), 3u);
  EXPECT_EQ(pulled[0], colours[1]);
  EXPECT_EQ(pulled[1], colours[0]);
  EXPECT_EQ(pulled[2], (Rgb{128, 128, 128}));  // out of range: grey
}

}  // namespace
}  // namespace isocorr
