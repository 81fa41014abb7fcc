#include "core/maps/manhattan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/sim/simulator.h"
#include "core/maps/submap.h"

namespace partslam {
namespace {

// Signed difference to the nearest multiple of 90 degrees [rad], in [-45, 45) degrees.
double residual_mod_quarter(double a) {
  const double q = std::numbers::pi / 2;
  return a - q * std::floor(a / q + 0.5);
}

TEST(ManhattanAngle, AxisAlignedRectangleNeedsNoRotation) {
  Points2 points;
  for (int i = 0; i < 50; ++i) {
    // Walls off the bin edges: points exactly on an edge would split between two bins by rounding.
    points.emplace_back(0.1 * i, 0.05);
    points.emplace_back(0.1 * i, 3.05);
    points.emplace_back(0.05, 0.06 * i);
    points.emplace_back(5.05, 0.06 * i);
  }
  EXPECT_NEAR(residual_mod_quarter(manhattan_angle(points)), 0.0, 0.1 * kDegree);
  const double a = manhattan_angle(transform(Pose2{0.0, 0.0, 25.0 * kDegree}, points));
  EXPECT_NEAR(residual_mod_quarter(a + 25.0 * kDegree), 0.0, 0.1 * kDegree);
  EXPECT_GE(a, 0.0);
  EXPECT_LT(a, std::numbers::pi / 2);
}

// Wall points every 0.05 m along a segment.
void add_wall(Points2& points, const Vec2& from, const Vec2& to) {
  const int n = static_cast<int>((to - from).norm() / 0.05);
  for (int i = 0; i <= n; ++i) points.push_back(from + (to - from) * (static_cast<double>(i) / n));
}

// A building along the axes with a wing turned by 20 degrees: the wing's direction is found (modulo 90 deg), the
// axes and the diagonals are not reported, and a building without the wing has none.
TEST(WallDirections, FindsAWingBuiltAtAnotherAngleAndNothingInAManhattanBuilding) {
  Points2 building;
  for (int k = 0; k < 6; ++k) {
    add_wall(building, {0.0, 2.0 * k + 0.3}, {20.0, 2.0 * k + 0.3});  // corridors along x
    add_wall(building, {4.0 * k + 0.3, 0.0}, {4.0 * k + 0.3, 10.0});  // and along y
  }
  add_wall(building, {0.0, 12.0}, {8.0, 20.0});  // a diagonal wall: searched by the eight families anyway
  EXPECT_TRUE(wall_directions(building).empty());
  Points2 with_wing = building;
  const Pose2 wing{30.0, 0.0, 20.0 * kDegree};
  for (int k = 0; k < 4; ++k) {
    add_wall(with_wing, wing * Vec2(0.0, 2.0 * k), wing * Vec2(12.0, 2.0 * k));
    add_wall(with_wing, wing * Vec2(3.0 * k, 0.0), wing * Vec2(3.0 * k, 6.0));
  }
  const std::vector<double> directions = wall_directions(with_wing);
  ASSERT_EQ(directions.size(), 1u);
  EXPECT_NEAR(directions[0], 20.0 * kDegree, 1.0 * kDegree);
  // Turned by a quarter turn, the same wing is at the same direction (modulo 90 degrees).
  const std::vector<double> turned = wall_directions(transform(Pose2{0.0, 0.0, 90.0 * kDegree}, with_wing));
  ASSERT_EQ(turned.size(), 1u);
  EXPECT_NEAR(turned[0], 20.0 * kDegree, 1.0 * kDegree);
  WallDirectionConfig strict;
  strict.min_share = 0.9;
  EXPECT_TRUE(wall_directions(with_wing, strict).empty());
  WallDirectionConfig long_walls;
  long_walls.min_length = 100.0;  // the wing has about 70 m of walls
  EXPECT_TRUE(wall_directions(with_wing, long_walls).empty());
  long_walls.min_length = 50.0;
  EXPECT_EQ(wall_directions(with_wing, long_walls).size(), 1u);
  EXPECT_TRUE(wall_directions({}).empty());
}

// Simulated submaps (walls along the world axes) turned by known angles: the alignment must undo the
// turn up to a multiple of 90 degrees.
TEST(ManhattanAngle, RecoversKnownRotationsOfSimulatedSubmaps) {
  SubmapConfig config;
  config.align = false;
  const Submaps maps = build_submaps(simulate().scans, config);
  ASSERT_GT(maps.size(), 100u);
  int checked = 0;
  double worst = 0.0;
  for (std::size_t k = 0; k < maps.size(); k += 11) {
    for (const double degrees : {0.4, 3.0, 17.0, 45.0, 62.5, 89.7, -20.0, 135.0}) {
      const double turn = degrees * kDegree;
      const double a = manhattan_angle(transform(Pose2{0.0, 0.0, turn}, maps[k].points));
      ASSERT_GE(a, 0.0);
      ASSERT_LT(a, std::numbers::pi / 2);
      const double r = std::abs(residual_mod_quarter(a + turn));
      worst = std::max(worst, r);
      EXPECT_LT(r, 1.0 * kDegree) << "submap " << k << " turned by " << degrees << " deg";
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);
  RecordProperty("worst_residual_deg", std::to_string(worst / kDegree));
}

// A laser at the centre of a 6 x 4 m room, its beams every degree, the room turned by `room` and the laser by
// `heading` in the world.
Scan room_scan(double room, double heading) {
  Scan s;
  s.T_world_laser = {1.0, -2.0, heading};
  for (int b = 0; b < 360; ++b) {
    const double a = b * std::numbers::pi / 180;  // in the laser frame
    const double w = a + heading - room;           // in the room's frame
    const double r = std::min(3.0 / std::max(std::abs(std::cos(w)), 1e-9), 2.0 / std::max(std::abs(std::sin(w)), 1e-9));
    s.points_laser.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return s;
}

TEST(LogWallAxis, FindsTheRoomsTurnModuloAQuarterTurnWhateverTheLasersHeading) {
  for (const double room : {0.0, 0.2, -0.5, 0.7}) {
    for (const double heading : {0.0, 1.0, -2.5}) {
      const double got = log_wall_axis({room_scan(room, heading)});
      const double want = std::remainder(room, std::numbers::pi / 2);
      EXPECT_NEAR(std::remainder(got - want, std::numbers::pi / 2), 0.0, 0.01) << room << " " << heading;
      EXPECT_LE(std::abs(got), std::numbers::pi / 4 + 1e-12);
    }
  }
}

TEST(LogWallAxis, NoSurfaceGivesNoTurn) {
  Scan sparse;
  sparse.points_laser = {{1, 0}, {0, 5}, {-9, 0}};  // no three within 0.5 m of each other
  EXPECT_EQ(log_wall_axis({sparse}), 0.0);
  EXPECT_EQ(log_wall_axis({}), 0.0);
}

}  // namespace
}  // namespace partslam
