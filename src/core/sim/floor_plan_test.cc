#include "core/sim/floor_plan.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace partslam {
namespace {

struct Built {
  FloorPlan plan;
  std::vector<Vec2> path;
};

// The plan with clutter kept clear of one lap of the corridor loop.
Built build(const FloorPlanConfig& config, std::uint64_t seed) {
  Rng rng(seed);
  Built b{make_floor_plan(config, rng), {}};
  b.path = b.plan.loop;
  add_clutter(config, b.path, 0.6, rng, &b.plan);
  return b;
}

TEST(FloorPlan, WallsAreAxisAlignedInsideTheBuilding) {
  const Built b = build({}, 3);
  EXPECT_EQ(b.plan.bounds.width(), 28.0);
  for (const Segment2& w : b.plan.walls) {
    EXPECT_TRUE(w.a.x() == w.b.x() || w.a.y() == w.b.y());
    EXPECT_GT((w.b - w.a).norm(), 0.0);
    for (const Vec2& p : {w.a, w.b}) {
      EXPECT_TRUE(p.x() >= 0.0 && p.x() <= 28.0 && p.y() >= 0.0 && p.y() <= 20.0);
    }
  }
}

TEST(FloorPlan, EveryRoomHasAnOpenDoorOfTheConfiguredWidth) {
  const FloorPlanConfig config;
  const Built b = build(config, 4);
  const RayCaster caster(b.plan.walls);
  ASSERT_GE(b.plan.rooms.size(), 12u);
  for (const Room& r : b.plan.rooms) {
    ASSERT_TRUE(r.has_door);
    const Vec2 n = r.door_normal, t(-n.y(), n.x());
    // From the corridor side, straight through the door into the room: nothing within 0.5 m past the wall.
    EXPECT_TRUE(std::isinf(caster.cast(r.door_centre + 0.5 * n, -n, 1.0)));
    // Just beside the gap the wall is there.
    for (const double side : {-1.0, 1.0}) {
      const Vec2 beside = r.door_centre + side * (config.door_width / 2 + 0.05) * t;
      EXPECT_NEAR(caster.cast(beside + 0.5 * n, -n, 1.0), 0.5, 1e-9);
    }
  }
}

TEST(FloorPlan, CorridorLoopIsClosedAndClearOfWallsAndClutter) {
  for (const bool cross : {true, false}) {
    FloorPlanConfig config;
    config.cross_corridor = cross;
    config.corridor_clutter = 40;
    const Built b = build(config, 5);
    const RayCaster caster(b.plan.walls);
    ASSERT_GE(b.plan.loop.size(), 5u);
    EXPECT_EQ(b.plan.loop.front(), b.plan.loop.back());
    EXPECT_GT(b.plan.clutter.size(), 20u);
    for (std::size_t k = 0; k + 1 < b.plan.loop.size(); ++k) {
      const Vec2 e = b.plan.loop[k + 1] - b.plan.loop[k];
      EXPECT_TRUE(e.x() == 0.0 || e.y() == 0.0);
      EXPECT_TRUE(std::isinf(caster.cast(b.plan.loop[k], e.normalized(), e.norm()))) << "leg " << k;
      for (const Box2& box : b.plan.clutter)
        EXPECT_GE(distance(Segment2{b.plan.loop[k], b.plan.loop[k + 1]}, box), 0.6);
    }
  }
}

TEST(FloorPlan, SameRngGivesSamePlan) {
  const Built a = build({}, 9), b = build({}, 9), c = build({}, 10);
  ASSERT_EQ(a.plan.walls.size(), b.plan.walls.size());
  for (std::size_t k = 0; k < a.plan.walls.size(); ++k) {
    EXPECT_EQ(a.plan.walls[k].a, b.plan.walls[k].a);
    EXPECT_EQ(a.plan.walls[k].b, b.plan.walls[k].b);
  }
  EXPECT_FALSE(a.plan.walls.size() == c.plan.walls.size() && a.plan.walls[10].a == c.plan.walls[10].a &&
               a.plan.rooms[0].door_centre == c.plan.rooms[0].door_centre);
}

TEST(SegmentBoxDistance, KnownAnswers) {
  const Box2 box{0.0, 1.0, 0.0, 1.0};
  EXPECT_EQ(distance(Segment2{{-1.0, 0.5}, {2.0, 0.5}}, box), 0.0);  // crosses
  EXPECT_EQ(distance(Segment2{{0.2, 0.2}, {0.3, 0.3}}, box), 0.0);   // inside
  EXPECT_DOUBLE_EQ(distance(Segment2{{-1.0, 2.0}, {2.0, 2.0}}, box), 1.0);
  EXPECT_DOUBLE_EQ(distance(Segment2{{2.0, 2.0}, {3.0, 3.0}}, box), std::sqrt(2.0));
  EXPECT_NEAR(distance(Segment2{{0.0, 2.5}, {2.5, 0.0}}, box), 0.5 / std::sqrt(2.0), 1e-12);  // to (1, 1)
}

TEST(FloorPlan, RejectsBadConfig) {
  FloorPlanConfig config;
  config.door_width = 0.0;
  Rng rng(1);
  EXPECT_THROW(make_floor_plan(config, rng), InputError);
}

}  // namespace
}  // namespace partslam
