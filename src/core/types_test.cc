#include "core/types.h"

#include <gtest/gtest.h>

namespace partslam {
namespace {

TEST(Pose2, ComposeWithInverseIsIdentity) {
  const Pose2 T_a_b{1.5, -2.0, 0.7};
  const Pose2 I = T_a_b * T_a_b.inverse();
  EXPECT_NEAR(I.x, 0.0, 1e-12);
  EXPECT_NEAR(I.y, 0.0, 1e-12);
  EXPECT_NEAR(I.theta, 0.0, 1e-12);
}

TEST(Pose2, TransformsPointsLikeComposition) {
  const Pose2 T_a_b{1.0, 2.0, std::numbers::pi / 2};
  const Pose2 T_b_c{3.0, 0.0, 0.3};
  const Vec2 p_c{0.5, -1.0};
  const Vec2 direct = (T_a_b * T_b_c) * p_c;
  const Vec2 chained = T_a_b * (T_b_c * p_c);
  EXPECT_NEAR((direct - chained).norm(), 0.0, 1e-12);
  EXPECT_NEAR((T_a_b * Vec2(1, 0) - Vec2(1, 3)).norm(), 0.0, 1e-12);
}

TEST(WrapAngle, StaysInHalfOpenInterval) {
  EXPECT_NEAR(wrap_angle(3 * std::numbers::pi), std::numbers::pi, 1e-12);
  EXPECT_NEAR(wrap_angle(-0.5), -0.5, 1e-12);
  EXPECT_NEAR(wrap_angle(2 * std::numbers::pi + 0.25), 0.25, 1e-12);
}

TEST(Box2, AreaAndContainment) {
  const Box2 b{0, 2, 1, 4};
  EXPECT_DOUBLE_EQ(b.area(), 6.0);
  EXPECT_TRUE(b.contains({1, 1}));
  EXPECT_FALSE(b.contains({2, 1}));
  EXPECT_DOUBLE_EQ((Box2{1, 0, 0, 1}).area(), 0.0);
}

TEST(Thinned, KeepsEveryKthPointSoThatAtMostTheLimitRemain) {
  Points2 points;
  for (int i = 0; i < 10; ++i) points.emplace_back(i, 0.0);
  EXPECT_EQ(thinned(points, 10), points);
  EXPECT_EQ(thinned(points, 20), points);
  const Points2 half = thinned(points, 5);  // stride 2
  ASSERT_EQ(half.size(), 5u);
  for (std::size_t k = 0; k < half.size(); ++k) EXPECT_EQ(half[k].x(), 2.0 * static_cast<double>(k));
  EXPECT_EQ(thinned(points, 4).size(), 4u);  // stride 3: points 0, 3, 6, 9
  EXPECT_EQ(thinned(points, 4).back().x(), 9.0);
  EXPECT_EQ(thinned(points, 3).size(), 3u);  // stride 4: points 0, 4, 8
  EXPECT_TRUE(thinned(Points2{}, 3).empty());
}

}  // namespace
}  // namespace partslam
