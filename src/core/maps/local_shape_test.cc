#include "core/maps/local_shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>

#include "core/error.h"

namespace partslam {
namespace {

// Points every 0.05 m along an L: a wall along x from (0, 0) to (2, 0) and one along y from (0, 0) to (0, 2),
// shifted far from the origin (the moments must stay well conditioned there).
Points2 l_shape(const Vec2& at) {
  Points2 p;
  for (int i = 0; i <= 40; ++i) p.push_back(at + Vec2(0.05 * i, 0.0));
  for (int i = 1; i <= 40; ++i) p.push_back(at + Vec2(0.0, 0.05 * i));
  return p;
}

TEST(LocalShape, WallPointsAreLinesAndTheCornerIsNot) {
  const Points2 p = l_shape({1000.0, -2000.0});
  const std::vector<double> c = cornerness(p, 0.5);
  ASSERT_EQ(c.size(), p.size());
  EXPECT_GT(c[0], 0.2);    // the corner
  EXPECT_LT(c[30], 1e-6);  // 1.5 m along the x wall
  EXPECT_LT(c[70], 1e-6);  // 1.5 m along the y wall
  EXPECT_GT(c[5], c[10]);  // falls off along the wall
}

TEST(LocalShape, CountsNeighboursWithinTheRadiusAcrossBuckets) {
  // Bucket cells of side 0.5 m: points on either side of a cell border still see each other.
  const Points2 p{{0.49, 0.0}, {0.51, 0.0}, {0.98, 0.0}, {1.2, 0.0}, {-0.3, 0.0}};
  const std::vector<LocalShape> s = local_shapes(p, 0.5);
  EXPECT_EQ(s[0].neighbours, 3);  // itself, 0.51 and 0.98 (0.49 m away, next cell); not -0.3 (0.79 m)
  EXPECT_EQ(s[1].neighbours, 3);  // itself, 0.49 (previous cell), 0.98
  EXPECT_EQ(s[2].neighbours, 4);  // itself, 0.49, 0.51, 1.2
  EXPECT_EQ(s[3].neighbours, 2);  // itself, 0.98
  EXPECT_EQ(s[4].neighbours, 1);
  EXPECT_LT(s[2].cornerness(), 1e-9);        // collinear
  EXPECT_DOUBLE_EQ(s[4].cornerness(), 1.0);  // alone: nothing says it lies on a line
}

TEST(LocalShape, EigenvaluesOfASquareAndAnOrderThatDoesNotMatter) {
  const Points2 square{{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  const std::vector<LocalShape> s = local_shapes(square, 2.0);
  for (const LocalShape& shape : s) {
    EXPECT_EQ(shape.neighbours, 4);
    EXPECT_NEAR(shape.lambda_min, 0.25, 1e-12);
    EXPECT_NEAR(shape.lambda_max, 0.25, 1e-12);
    EXPECT_NEAR(shape.cornerness(), 1.0, 1e-12);
  }
  Points2 reversed(square.rbegin(), square.rend());
  EXPECT_EQ(cornerness(reversed, 2.0), cornerness(square, 2.0));
  EXPECT_TRUE(local_shapes({}, 1.0).empty());
}

TEST(LocalShape, ABareCorridorLeavesItsAxisUnconstrainedAndARoomLeavesNothing) {
  // Two walls 2 m apart along a direction at 30 degrees: the axis is the weak direction.
  const double a = 30.0 * std::numbers::pi / 180;
  const Vec2 along(std::cos(a), std::sin(a)), across(-std::sin(a), std::cos(a));
  Points2 corridor;
  for (int i = 0; i <= 80; ++i)
    corridor.push_back(0.05 * i * along + across), corridor.push_back(0.05 * i * along - across);
  const std::vector<LocalShape> shapes = local_shapes(corridor, 0.5);
  EXPECT_NEAR(std::abs(std::cos(shapes[40].angle - a)), 1.0, 1e-9);  // a wall point's angle runs along it
  const std::optional<Vec2> weak = unconstrained_direction(wall_scatter(shapes), 0.1);
  ASSERT_TRUE(weak.has_value());
  EXPECT_NEAR(std::abs(weak->dot(along)), 1.0, 1e-9);
  EXPECT_FALSE(unconstrained_direction(wall_scatter(shapes), 0.0).has_value());  // off
  // The same corridor closed by a wall across it at its end: both directions are fixed.
  Points2 closed = corridor;
  for (int j = -20; j <= 20; ++j) closed.push_back(4.0 * along + 0.05 * j * across);
  EXPECT_FALSE(unconstrained_direction(wall_scatter(local_shapes(closed, 0.5)), 0.1).has_value());
  EXPECT_FALSE(unconstrained_direction(wall_scatter({}), 0.1).has_value());  // no wall
}

TEST(LocalShape, RejectsAnAbsurdRadius) {
  EXPECT_THROW(local_shapes({{0, 0}}, 0.0), InputError);
  EXPECT_THROW(local_shapes({{0, 0}}, -1.0), InputError);
  EXPECT_THROW(local_shapes({{0, 0}}, std::nan("")), InputError);
  EXPECT_THROW(local_shapes({{0, 0}, {std::nan(""), 0}}, 1.0), InputError);
  EXPECT_THROW(local_shapes({{1e300, 0}}, 1.0), InputError);
}

}  // namespace
}  // namespace partslam
