// The rasteriser on triangles whose pixels are known by hand.
#include "isocorr/render/rasteriser.h"

#include <gtest/gtest.h>

#include <cmath>

namespace isocorr {
namespace {

constexpr Rgb kWhite = {255, 255, 255};

ScreenVertex corner(double x, double y, double depth, Eigen::Vector3d colour) { return {x, y, depth, colour}; }

TEST(Rasteriser, DrawsExactlyThePixelsWhoseCentresLieInside) {
  RgbImage image(8, 8, kWhite);
  Rasteriser rasteriser(image);
  const Eigen::Vector3d red(255, 0, 0);
  // Right angle at (1, 1), legs of 6 pixels: centres (x+0.5, y+0.5) with x, y >= 1, x + y <= 7.
  rasteriser.draw_triangle(corner(1, 1, 0, red), corner(7, 1, 0, red), corner(1, 7, 0, red));
  int drawn = 0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const bool inside = x >= 1 && y >= 1 && x + y <= 7;
      EXPECT_EQ(image.at(x, y), inside ? (Rgb{255, 0, 0}) : kWhite) << x << "," << y;
      EXPECT_EQ(std::isinf(rasteriser.depth_at(x, y)), !inside) << x << "," << y;
      drawn += inside;
    }
  EXPECT_EQ(drawn, 21);
}

TEST(Rasteriser, EitherWindingDrawsTheSame) {
  RgbImage forward(8, 8, kWhite), backward(8, 8, kWhite);
  const Eigen::Vector3d blue(0, 0, 255);
  Rasteriser(forward).draw_triangle(corner(0.2, 0.3, 0, blue), corner(7.6, 2, 0, blue), corner(3, 7.9, 0, blue));
  Rasteriser(backward).draw_triangle(corner(0.2, 0.3, 0, blue), corner(3, 7.9, 0, blue), corner(7.6, 2, 0, blue));
  EXPECT_EQ(forward.pixels, backward.pixels);
}

TEST(Rasteriser, InterpolatesCornerColoursBarycentrically) {
  RgbImage image(8, 8, kWhite);
  Rasteriser(image).draw_triangle(corner(0, 0, 0, {255, 0, 0}), corner(8, 0, 0, {0, 255, 0}),
                                  corner(0, 8, 0, {0, 0, 255}));
  // Centre (1.5, 1.5): weights 0.625, 0.1875, 0.1875.
  EXPECT_EQ(image.at(1, 1), (Rgb{159, 48, 48}));
  // Centre (0.5, 6.5): weights 0.125, 0.0625, 0.8125.
  EXPECT_EQ(image.at(0, 6), (Rgb{32, 16, 207}));
}

TEST(Rasteriser, TheNearerTriangleShowsWhicheverIsDrawnFirst) {
  const Eigen::Vector3d near_colour(255, 0, 0), far_colour(0, 0, 255);
  auto square_half = [](double depth, Eigen::Vector3d colour, Rasteriser& r) {
    r.draw_triangle(corner(0, 0, depth, colour), corner(4, 0, depth, colour), corner(0, 4, depth, colour));
  };
  for (bool near_first : {true, false}) {
    RgbImage image(4, 4, kWhite);
    Rasteriser rasteriser(image);
    if (near_first) square_half(1, near_colour, rasteriser);
    square_half(5, far_colour, rasteriser);
    if (!near_first) square_half(1, near_colour, rasteriser);
    EXPECT_EQ(image.at(1, 1), (Rgb{255, 0, 0})) << near_first;
    EXPECT_DOUBLE_EQ(rasteriser.depth_at(1, 1), 1);
  }
}

TEST(Rasteriser, DepthIsInterpolatedSoCrossingTrianglesSplitThePicture) {
  RgbImage image(8, 2, kWhite);
  Rasteriser rasteriser(image);
  // A flat red strip at depth 4 and a blue one tilted from depth 0 (left) to 8 (right):
  // blue shows where its depth is below 4, i.e. on the left half.
  const Eigen::Vector3d red(255, 0, 0), blue(0, 0, 255);
  rasteriser.draw_triangle(corner(0, 0, 4, red), corner(8, 0, 4, red), corner(0, 2, 4, red));
  rasteriser.draw_triangle(corner(8, 0, 4, red), corner(8, 2, 4, red), corner(0, 2, 4, red));
  rasteriser.draw_triangle(corner(0, 0, 0, blue), corner(8, 0, 8, blue), corner(0, 2, 0, blue));
  rasteriser.draw_triangle(corner(8, 0, 8, blue), corner(8, 2, 8, blue), corner(0, 2, 0, blue));
  for (int x = 0; x < 8; ++x) EXPECT_EQ(image.at(x, 1), x < 4 ? (Rgb{0, 0, 255}) : (Rgb{255, 0, 0})) << x;
}

TEST(Rasteriser, ClipsToTheImageAndSkipsEdgeOnTriangles) {
  RgbImage image(4, 4, kWhite);
  Rasteriser rasteriser(image);
  const Eigen::Vector3d green(0, 255, 0);
  rasteriser.draw_triangle(corner(1, 1, 0, green), corner(2, 2, 0, green), corner(3, 3, 0, green));  // a line
  rasteriser.draw_triangle(corner(-1e6, -5, 0, green), corner(1e6, -5, 0, green), corner(2, -1, 0, green));  // above
  EXPECT_EQ(image.pixels, RgbImage(4, 4, kWhite).pixels);
  rasteriser.draw_triangle(corner(-100, -100, 0, green), corner(100, -100, 0, green), corner(0, 100, 0, green));
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) EXPECT_EQ(image.at(x, y), (Rgb{0, 255, 0}));
}

}  // namespace
}  // namespace isocorr
