#include "core/sim/ray_caster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/random.h"
#include "core/sim/simulator.h"

namespace partslam {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(IntersectRay, KnownAnswers) {
  const Segment2 wall{{5.0, -10.0}, {5.0, 10.0}};
  EXPECT_EQ(intersect_ray({0.0, 0.0}, {1.0, 0.0}, wall), 5.0);
  EXPECT_EQ(intersect_ray({0.0, 0.0}, {-1.0, 0.0}, wall), kInf);  // behind the origin
  EXPECT_EQ(intersect_ray({0.0, 0.0}, {0.0, 1.0}, wall), kInf);   // parallel
  EXPECT_EQ(intersect_ray({0.0, 11.0}, {1.0, 0.0}, wall), kInf);  // passes beyond its end
  EXPECT_EQ(intersect_ray({0.0, 10.0}, {1.0, 0.0}, wall), 5.0);   // endpoints count as hits
  EXPECT_NEAR(intersect_ray({1.0, 1.0}, {std::sqrt(0.5), std::sqrt(0.5)}, wall), 4.0 * std::sqrt(2.0), 1e-12);
}

TEST(RayCaster, NearestOfSeveralWallsAndMaxRange) {
  const RayCaster caster({{{5.0, -1.0}, {5.0, 1.0}}, {{3.0, -1.0}, {3.0, 1.0}}, {{40.0, -1.0}, {40.0, 1.0}}});
  EXPECT_EQ(caster.cast({0.0, 0.0}, {1.0, 0.0}, 30.0), 3.0);
  EXPECT_EQ(caster.cast({4.0, 0.0}, {1.0, 0.0}, 30.0), 1.0);
  EXPECT_EQ(caster.cast({6.0, 0.0}, {1.0, 0.0}, 30.0), kInf);  // next wall at 34 m: beyond max range
  EXPECT_EQ(caster.cast({6.0, 0.0}, {1.0, 0.0}, 40.0), 34.0);
  EXPECT_EQ(caster.cast({0.0, 5.0}, {1.0, 0.0}, 100.0), kInf);    // misses everything
  EXPECT_EQ(caster.cast({-20.0, 0.0}, {1.0, 0.0}, 100.0), 23.0);  // origin outside the grid
  EXPECT_EQ(RayCaster({}).cast({0.0, 0.0}, {1.0, 0.0}, 10.0), kInf);
}

// The grid walk must return exactly the brute-force minimum, for rays from anywhere in a simulated building.
TEST(RayCaster, EqualsBruteForceOnSimulatedBuilding) {
  const SimulatedLog log = simulate();
  for (const double cell : {0.5, 0.37, 2.0}) {
    const RayCaster caster(log.plan.walls, cell);
    Rng rng(7);
    for (int k = 0; k < 20000; ++k) {
      Vec2 origin(rng.uniform(-2.0, 30.0), rng.uniform(-2.0, 22.0));
      if (k % 7 == 0) origin = (2.0 * origin).array().round() / 2.0;  // on grid lines (and walls) of 0.5 m
      const double a = rng.uniform(-std::numbers::pi, std::numbers::pi);
      const Vec2 axes[4] = {{1.0, 0.0}, {0.0, 1.0}, {-1.0, 0.0}, {0.0, -1.0}};
      // Every 10th ray is axis-aligned: it runs along grid lines, and sometimes along a wall.
      const Vec2 d = k % 10 == 0 ? axes[(k / 10) % 4] : Vec2(std::cos(a), std::sin(a));
      const double max_range = rng.uniform(1.0, 40.0);
      ASSERT_EQ(caster.cast(origin, d, max_range), cast_ray_brute_force(log.plan.walls, origin, d, max_range))
          << "origin " << origin.transpose() << " dir " << d.transpose() << " cell " << cell;
    }
  }
}

TEST(RayCaster, RejectsBadInput) {
  EXPECT_THROW(RayCaster({}, 0.0), InputError);
  EXPECT_THROW(RayCaster({{{0.0, 0.0}, {std::nan(""), 1.0}}}), InputError);
}

}  // namespace
}  // namespace partslam
