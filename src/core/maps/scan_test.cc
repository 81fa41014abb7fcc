#include "core/maps/scan.h"

#include <gtest/gtest.h>

#include <vector>

namespace partslam {
namespace {

std::vector<Vec2> tangents(const Points2& points, double max_range) {
  std::vector<Vec2> out;
  for_each_surface_tangent(points, max_range, [&](const Vec2& d) { out.push_back(d); });
  return out;
}

TEST(SurfaceTangent, AWallGivesItsChordAtEveryInnerEndpoint) {
  Points2 wall;  // a wall 2 m ahead, across the laser's x axis, endpoints 0.1 m apart
  for (int i = 0; i < 6; ++i) wall.emplace_back(2.0, 0.1 * i);
  const std::vector<Vec2> t = tangents(wall, 10.0);
  ASSERT_EQ(t.size(), 4u);  // the first and last endpoints have one neighbour only
  for (const Vec2& d : t) {
    EXPECT_NEAR(d.x(), 0.0, 1e-12);
    EXPECT_NEAR(d.y(), 0.2, 1e-12);  // p[i + 1] - p[i - 1], not normalised
  }
}

TEST(SurfaceTangent, AJumpBetweenObjectsTheRangeCapAndRepeatedPointsGiveNone) {
  // Three endpoints on one wall, then a jump of 1 m to another object: only the middle of the first three counts.
  const Points2 jump{{2.0, 0.0}, {2.0, 0.1}, {2.0, 0.2}, {3.0, 0.2}, {3.0, 0.3}};
  EXPECT_EQ(tangents(jump, 10.0).size(), 1u);
  // The same wall beyond the range cap.
  const Points2 far{{2.0, 0.0}, {2.0, 0.1}, {2.0, 0.2}};
  EXPECT_EQ(tangents(far, 1.5).size(), 0u);
  EXPECT_EQ(tangents(far, 2.1).size(), 1u);
  // A chord shorter than 1e-6 m (the neighbours coincide) has no direction.
  const Points2 same{{2.0, 0.0}, {2.0, 0.1}, {2.0, 0.0}};
  EXPECT_EQ(tangents(same, 10.0).size(), 0u);
  EXPECT_EQ(tangents(Points2{}, 10.0).size(), 0u);
}

}  // namespace
}  // namespace partslam
