// normalise_coordinates: the range it brings every mesh into, its exactness, and what it refuses.
#include "isocorr/mesh/coordinate_normalisation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

double largest_half_extent(const std::vector<Vec3>& points) {
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return (hi / 2 - lo / 2).maxCoeff();
}

double largest_coordinate(const std::vector<Vec3>& points) {
  double largest = 0;
  for (const Vec3& p : points) largest = std::max(largest, p.cwiseAbs().maxCoeff());
  return largest;
}

TEST(CoordinateNormalisation, BringsAnyScaleIntoTheSameRangeAndBackExactly) {
  for (const double scale : {1.0, 1e308, -1e308, 1e-160, 1e160, 3e-300, 7.0}) {
    const std::vector<Vec3> input = {Vec3(0.1, -0.2, 0.3) * scale, Vec3(-0.4, 0.5, 0.25) * scale,
                                     Vec3(0.05, 0.45, -0.35) * scale};
    std::vector<Vec3> points = input;
    const CoordinateNormalisation normalisation = normalise_coordinates(points);
    const double half = largest_half_extent(points);
    EXPECT_GE(half, 0.5) << scale;
    EXPECT_LT(half, 1.0) << scale;
    EXPECT_LE(largest_coordinate(points), 3.0) << scale;
    for (size_t i = 0; i < input.size(); ++i) EXPECT_EQ(normalisation.to_input(points[i]), input[i]) << scale;
  }
}

TEST(CoordinateNormalisation, MovesABoxFarFromTheOriginOntoItWithoutRounding) {
  const std::vector<Vec3> input = {Vec3(1e9 + 0.125, 3, -2e12), Vec3(1e9 - 0.5, 4, -2e12 + 1),
                                   Vec3(1e9 + 0.25, 3.5, -2e12 + 0.5)};
  std::vector<Vec3> points = input;
  const CoordinateNormalisation normalisation = normalise_coordinates(points);
  EXPECT_LE(largest_coordinate(points), 3.0);
  EXPECT_NE(normalisation.offset, Vec3::Zero());
  for (size_t i = 0; i < input.size(); ++i) EXPECT_EQ(normalisation.to_input(points[i]), input[i]);
  // Differences of coordinates survive exactly, only scaled by the power of two.
  const double scale = std::ldexp(1.0, normalisation.exponent);
  EXPECT_EQ(points[0] - points[1], (input[0] - input[1]) * scale);
}

TEST(CoordinateNormalisation, RefusesCoincidentAndNonFinitePoints) {
  std::vector<Vec3> same(5, Vec3(1e300, -2, 3));
  EXPECT_THROW(normalise_coordinates(same), InputError);
  std::vector<Vec3> infinite = {Vec3(0, 0, 0), Vec3(std::numeric_limits<double>::infinity(), 0, 0)};
  EXPECT_THROW(normalise_coordinates(infinite), InputError);
  std::vector<Vec3> none;
  EXPECT_THROW(normalise_coordinates(none), InputError);
}

}  // namespace
}  // namespace isocorr
