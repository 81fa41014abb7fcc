#include "core/sim/simulator.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

#include "core/error.h"
#include "core/maps/submap.h"

namespace partslam {
namespace {

double distance_to_walls(const Vec2& p, const Segments2& walls) {
  double best = std::numeric_limits<double>::infinity();
  for (const Segment2& s : walls) {
    const Vec2 e = s.b - s.a;
    const double t = std::clamp((p - s.a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (s.a + t * e - p).norm());
  }
  return best;
}

SimulatorConfig noise_free() {
  SimulatorConfig config;
  config.laser.range_sigma = 0.0;
  config.odometry = {0.0, 0.0, 0.0, 0.0, 0.0};
  return config;
}

TEST(Simulator, SameSeedGivesIdenticalLogDifferentSeedDoesNot) {
  const SimulatedLog a = simulate(), b = simulate();
  ASSERT_EQ(a.scans.size(), b.scans.size());
  for (std::size_t k = 0; k < a.scans.size(); ++k) {
    const Scan &sa = a.scans[k], &sb = b.scans[k];
    ASSERT_EQ(sa.timestamp, sb.timestamp);
    ASSERT_EQ(sa.T_world_laser.x, sb.T_world_laser.x);
    ASSERT_EQ(sa.T_world_laser.theta, sb.T_world_laser.theta);
    ASSERT_EQ(sa.T_world_odom.x, sb.T_world_odom.x);
    ASSERT_EQ(sa.T_world_odom.y, sb.T_world_odom.y);
    ASSERT_EQ(sa.T_world_odom.theta, sb.T_world_odom.theta);
    ASSERT_EQ(sa.points_laser, sb.points_laser) << "scan " << k;
  }
  SimulatorConfig other;
  other.seed = 2;
  const SimulatedLog c = simulate(other);
  const bool same_size = c.scans.size() == a.scans.size() && c.plan.walls.size() == a.plan.walls.size();
  EXPECT_FALSE(same_size && c.scans[100].points_laser == a.scans[100].points_laser);
}

TEST(Simulator, NoiseStreamsAreIndependentOfTheBuilding) {
  const SimulatedLog noisy = simulate(), exact = simulate(noise_free());
  ASSERT_EQ(noisy.plan.walls.size(), exact.plan.walls.size());
  ASSERT_EQ(noisy.scans.size(), exact.scans.size());
  for (std::size_t k = 0; k < noisy.scans.size(); ++k) {
    ASSERT_EQ(noisy.scans[k].T_world_laser.x, exact.scans[k].T_world_laser.x);
  }
}

// Known answer: a laser at a known pose facing a single wall sees it at the geometric distance.
TEST(Simulator, BeamRangesHitAWallAtTheExactDistance) {
  LaserSimConfig laser;
  const RayCaster caster({{{5.0, -10.0}, {5.0, 10.0}}});
  const std::vector<double> ranges = beam_ranges(caster, {0.0, 0.0, 0.0}, laser);
  ASSERT_EQ(ranges.size(), 181u);
  EXPECT_EQ(beam_angle(laser, 90), 0.0);
  EXPECT_EQ(ranges[90], 5.0);
  for (int i = 0; i < 181; ++i) {
    const double a = beam_angle(laser, i);
    if (std::abs(5.0 * std::tan(a)) < 9.99) {
      EXPECT_NEAR(ranges[i], 5.0 / std::cos(a), 1e-9) << "beam " << i;
    } else if (std::abs(5.0 * std::tan(a)) > 10.01) {
      EXPECT_TRUE(std::isinf(ranges[i])) << "beam " << i;
    }
  }
  // Turned by 90 degrees, the laser at (1, 2) faces the wall y = 7 head-on; the wall at x = 5 is then on
  // its right, hit by the first beam (-90 degrees) at 4 m.
  const RayCaster two({{{-10.0, 7.0}, {10.0, 7.0}}, {{5.0, -10.0}, {5.0, 10.0}}});
  const std::vector<double> turned = beam_ranges(two, {1.0, 2.0, std::numbers::pi / 2}, laser);
  EXPECT_NEAR(turned[90], 5.0, 1e-12);
  EXPECT_NEAR(turned[0], 4.0, 1e-12);
  // Beyond max range nothing is returned.
  laser.max_range = 4.5;
  EXPECT_TRUE(std::isinf(beam_ranges(caster, {0.0, 0.0, 0.0}, laser)[90]));
}

TEST(Simulator, NoiseFreePointsLieOnTheWalls) {
  const SimulatedLog log = simulate(noise_free());
  std::size_t checked = 0;
  for (std::size_t k = 0; k < log.scans.size(); k += 25) {
    const Scan& scan = log.scans[k];
    EXPECT_EQ(scan.num_beams, 181);
    EXPECT_GT(scan.points_laser.size(), 90u);  // indoors, few beams see nothing within 30 m
    for (const Vec2& p : points_world(scan)) {
      ASSERT_LT(distance_to_walls(p, log.plan.walls), 1e-9) << "scan " << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 10000u);
}

// Range noise: the same building and path without noise gives the true range of each beam.
TEST(Simulator, RangeNoiseHasTheConfiguredSigma) {
  const SimulatedLog noisy = simulate(), exact = simulate(noise_free());
  double sum = 0.0, sum2 = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < noisy.scans.size(); ++k) {
    const Points2 &a = noisy.scans[k].points_laser, &b = exact.scans[k].points_laser;
    if (a.size() != b.size()) continue;  // a beam near max range dropped in one of them
    for (std::size_t i = 0; i < a.size(); ++i) {
      const double e = a[i].norm() - b[i].norm();
      sum += e, sum2 += e * e, ++n;
    }
  }
  ASSERT_GT(n, 100000u);
  const double mean = sum / n, sigma = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 1e-4);
  EXPECT_NEAR(sigma, 0.01, 2e-4);
}

TEST(Simulator, TrajectoryIsContinuousTimedAndNeverCrossesAWall) {
  const SimulatedLog log = simulate();
  const RayCaster caster(log.plan.walls);
  ASSERT_GT(log.scans.size(), 1000u);
  for (std::size_t k = 1; k < log.scans.size(); ++k) {
    const Pose2 &p = log.scans[k - 1].T_world_laser, &q = log.scans[k].T_world_laser;
    ASSERT_GT(log.scans[k].timestamp, log.scans[k - 1].timestamp);
    const Vec2 step = q.translation() - p.translation();
    ASSERT_LE(step.norm(), 0.1 + 1e-12);
    ASSERT_LE(std::abs(wrap_angle(q.theta - p.theta)), 0.1 + 1e-12);
    if (step.norm() > 0) {
      ASSERT_TRUE(std::isinf(caster.cast(p.translation(), step.normalized(), step.norm()))) << "scan " << k;
    }
    ASSERT_GT(distance_to_walls(q.translation(), log.plan.walls), 0.3) << "scan " << k;
  }
}

// Loop closures (docs/DESIGN.md, "Tasks"): places seen again after more than 20 m of travel.
TEST(Simulator, TrajectoryRevisitsPlaces) {
  const SimulatedLog log = simulate();
  const std::vector<double> s = travel_distances(log.scans);
  std::size_t revisits = 0;
  for (std::size_t i = 0; i < log.scans.size(); i += 5) {
    for (std::size_t j = i + 1; j < log.scans.size(); j += 5) {
      const double d =
          (log.scans[i].T_world_laser.translation() - log.scans[j].T_world_laser.translation()).norm();
      if (d < 2.0 && s[j] - s[i] > 20.0) ++revisits;
    }
  }
  EXPECT_GT(revisits, 1000u);
  EXPECT_GT(s.back(), 100.0);
  EXPECT_LT(s.back(), 300.0);  // a few hundred submaps at most
}

TEST(Simulator, OdometryDriftGrowsButStaysBounded) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    SimulatorConfig config;
    config.seed = seed;
    const SimulatedLog log = simulate(config);
    const std::vector<double> s = travel_distances(log.scans);
    double early = 0.0, late = 0.0, worst = 0.0, worst_heading = 0.0;
    for (std::size_t k = 0; k < log.scans.size(); ++k) {
      const Scan& scan = log.scans[k];
      const double e = (scan.T_world_odom.translation() - scan.T_world_laser.translation()).norm();
      worst = std::max(worst, e);
      worst_heading =
          std::max(worst_heading, std::abs(wrap_angle(scan.T_world_odom.theta - scan.T_world_laser.theta)));
      if (s[k] < 10.0) {
        early = std::max(early, e);
      } else {
        late = std::max(late, e);
      }
    }
    EXPECT_EQ(log.scans[0].T_world_odom.x, log.scans[0].T_world_laser.x);
    EXPECT_GT(early, 0.0) << "seed " << seed;
    EXPECT_GT(late, 3 * early) << "seed " << seed;
    EXPECT_LT(worst, 5.0) << "seed " << seed;
    EXPECT_LT(worst_heading, 0.4) << "seed " << seed;
  }
  // Without odometry noise, odometry is the truth.
  const SimulatedLog exact = simulate(noise_free());
  for (const Scan& scan : exact.scans) {
    ASSERT_NEAR((scan.T_world_odom.translation() - scan.T_world_laser.translation()).norm(), 0.0, 1e-9);
    ASSERT_NEAR(wrap_angle(scan.T_world_odom.theta - scan.T_world_laser.theta), 0.0, 1e-9);
  }
}

TEST(Simulator, RingWithoutCrossCorridorAndOtherSettings) {
  SimulatorConfig config;
  config.seed = 11;
  config.building.cross_corridor = false;
  config.building.width = 22.0;
  config.route.laps = 3;
  config.route.room_visits = 0;
  config.laser.num_beams = 361;
  const SimulatedLog log = simulate(config);
  ASSERT_FALSE(log.scans.empty());
  EXPECT_EQ(log.scans[0].num_beams, 361);
  const std::vector<double> s = travel_distances(log.scans);
  // Ring centreline: (22 - 12) x (20 - 12) m, driven three times.
  EXPECT_NEAR(s.back(), 3 * 2 * (10.0 + 8.0), 1e-6);
}

TEST(Simulator, BadConfigThrowsNamingTheField) {
  const std::vector<std::pair<std::string, std::function<void(SimulatorConfig&)>>> cases = {
      {"building.width", [](SimulatorConfig& c) { c.building.width = 10.0; }},
      {"building.height", [](SimulatorConfig& c) { c.building.height = -1.0; }},
      {"building.corridor_width", [](SimulatorConfig& c) { c.building.corridor_width = 0.0; }},
      {"building.min_room_width", [](SimulatorConfig& c) { c.building.min_room_width = 1.0; }},
      {"building.max_room_width", [](SimulatorConfig& c) { c.building.max_room_width = 2.0; }},
      {"building.room_depth", [](SimulatorConfig& c) { c.building.room_depth = std::nan(""); }},
      {"building.clutter_per_room", [](SimulatorConfig& c) { c.building.clutter_per_room = -1; }},
      {"building.max_clutter_size", [](SimulatorConfig& c) { c.building.max_clutter_size = 0.1; }},
      {"route.laps", [](SimulatorConfig& c) { c.route.laps = 0; }},
      {"route.scan_spacing", [](SimulatorConfig& c) { c.route.scan_spacing = 0.0; }},
      {"route.scan_spacing", [](SimulatorConfig& c) { c.route.scan_spacing = 1e-6; }},  // far too many scans
      {"route.speed", [](SimulatorConfig& c) { c.route.speed = -1.0; }},
      {"route.clearance", [](SimulatorConfig& c) { c.route.clearance = 5.0; }},
      {"laser.num_beams", [](SimulatorConfig& c) { c.laser.num_beams = 1; }},
      {"laser.max_range",
       [](SimulatorConfig& c) { c.laser.max_range = std::numeric_limits<double>::infinity(); }},
      {"laser.range_sigma", [](SimulatorConfig& c) { c.laser.range_sigma = -0.1; }},
      {"laser.field_of_view", [](SimulatorConfig& c) { c.laser.field_of_view = 7.0; }},
      {"odometry.heading_sigma", [](SimulatorConfig& c) { c.odometry.heading_sigma = -1.0; }},
      {"odometry.scale_error", [](SimulatorConfig& c) { c.odometry.scale_error = 0.9; }},
  };
  for (const auto& [field, mutate] : cases) {
    SimulatorConfig config;
    mutate(config);
    try {
      simulate(config);
      ADD_FAILURE() << field << ": no exception";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr(field));
    }
  }
}

}  // namespace
}  // namespace partslam
