// KdTree: nearest and radius queries agree with brute force on random points, also when the
// tree holds only some of them.
#include "isocorr/util/kd_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

namespace isocorr {
namespace {

using Point = Eigen::Vector3d;

std::vector<Point> random_points(int count, std::mt19937& random) {
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  std::vector<Point> points(count);
  for (Point& p : points) p = Point(coordinate(random), coordinate(random), coordinate(random));
  return points;
}

int brute_nearest(const std::vector<Point>& points, const std::vector<int>& ids, const Point& query) {
  int best = -1;
  double best_squared = std::numeric_limits<double>::infinity();
  for (int id : ids)
    if (const double squared = (points[id] - query).squaredNorm(); squared < best_squared)
      best_squared = squared, best = id;
  return best;
}

TEST(KdTree, NearestAgreesWithBruteForce) {
  std::mt19937 random(7);
  const std::vector<Point> points = random_points(2000, random);
  std::vector<int> ids;  // every third point
  for (int i = 0; i < static_cast<int>(points.size()); i += 3) ids.push_back(i);
  const KdTree tree(points, ids);
  for (const Point& query : random_points(500, random))
    EXPECT_EQ(tree.nearest(query), brute_nearest(points, ids, query));
  for (int id : ids) EXPECT_EQ(tree.nearest(points[id]), id);
}

TEST(KdTree, WithinAgreesWithBruteForce) {
  std::mt19937 random(11);
  const std::vector<Point> points = random_points(1500, random);
  std::vector<int> all(points.size());
  for (int i = 0; i < static_cast<int>(all.size()); ++i) all[i] = i;
  const KdTree tree(points, all);
  for (const double radius : {0.0, 0.05, 0.2, 3.5}) {
    for (const Point& query : random_points(100, random)) {
      std::vector<int> found, expected;
      tree.within(query, radius, [&](int id) { found.push_back(id); });
      for (int id : all)
        if ((points[id] - query).squaredNorm() <= radius * radius) expected.push_back(id);
      std::sort(found.begin(), found.end());
      EXPECT_EQ(found, expected) << "radius " << radius;
    }
  }
}

TEST(KdTree, FindsCoincidentPointsAtRadiusZero) {
  const std::vector<Point> points = {Point(0, 0, 0), Point(1, 0, 0), Point(0, 0, 0), Point(0, 1, 0)};
  const KdTree tree(points, {0, 1, 2, 3});
  std::vector<int> found;
  tree.within(Point(0, 0, 0), 0.0, [&](int id) { found.push_back(id); });
  std::sort(found.begin(), found.end());
  EXPECT_EQ(found, (std::vector<int>{0, 2}));
}

TEST(KdTree, EmptyTreeHasNoNearest) {
  const std::vector<Point> points = {Point(0, 0, 0)};
  const KdTree tree(points, {});
  EXPECT_EQ(tree.nearest(Point(0, 0, 0)), -1);
  int visits = 0;
  tree.within(Point(0, 0, 0), 1.0, [&](int) { ++visits; });
  EXPECT_EQ(visits, 0);
}

}  // namespace
}  // namespace isocorr
