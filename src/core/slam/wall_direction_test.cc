#include "core/slam/wall_direction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace partslam {
namespace {

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

TEST(WallDirection, FindsTheRoomsTurnModuloAQuarterTurnWhateverTheLasersHeading) {
  for (const double room : {0.0, 0.2, -0.5, 0.7}) {
    for (const double heading : {0.0, 1.0, -2.5}) {
      const double got = wall_direction({room_scan(room, heading)});
      const double want = std::remainder(room, std::numbers::pi / 2);
      EXPECT_NEAR(std::remainder(got - want, std::numbers::pi / 2), 0.0, 0.01) << room << " " << heading;
      EXPECT_LE(std::abs(got), std::numbers::pi / 4 + 1e-12);
    }
  }
}

TEST(WallDirection, NoSurfaceGivesNoTurn) {
  Scan sparse;
  sparse.points_laser = {{1, 0}, {0, 5}, {-9, 0}};  // no three within 0.5 m of each other
  EXPECT_EQ(wall_direction({sparse}), 0.0);
  EXPECT_EQ(wall_direction({}), 0.0);
}

}  // namespace
}  // namespace partslam
