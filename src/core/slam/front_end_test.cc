#include "core/slam/front_end.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "core/error.h"
#include "core/testing/scan_index.h"
#include "core/evaluation/trajectory_check.h"
#include "core/sim/simulator.h"

namespace partslam {
namespace {

// A simulated log with the exact poses kept aside: what a raw log gives is odometry in both pose slots.
struct RawLog {
  Scans raw;
  Scans truth;
};

RawLog simulated_raw_log(double odometry_noise_scale) {
  SimulatorConfig config;
  config.route.laps = 1;
  config.route.room_visits = 1;
  config.odometry.translation_sigma *= odometry_noise_scale;
  config.odometry.heading_sigma *= odometry_noise_scale;
  config.odometry.turn_sigma *= odometry_noise_scale;
  config.odometry.heading_bias *= odometry_noise_scale;
  RawLog log;
  log.truth = simulate(config).scans;
  log.raw = log.truth;
  for (Scan& s : log.raw) s.T_world_laser = s.T_world_odom;
  return log;
}

TEST(FrontEnd, MakesBadOdometryLocallyConsistent) {
  const RawLog log = simulated_raw_log(5.0);
  const FrontEndResult fe = scan_match_log(log.raw);
  ASSERT_EQ(fe.scans.size(), log.raw.size());
  EXPECT_TRUE(fe.stats.odometry_moves);
  EXPECT_EQ(fe.stats.time_reversals, 0u);
  EXPECT_LT(fe.stats.rejected, fe.scans.size() / 100);
  const auto index = testing::identity_index(log.raw.size());
  const Consistency odometry = local_consistency(log.raw, log.truth, index);
  const Consistency matched = local_consistency(fe.scans, log.truth, index);
  EXPECT_GT(odometry.median, 0.03) << odometry.median;  // the premise: odometry alone smears a 2 m submap
  EXPECT_LT(matched.median, 0.03) << matched.median;
  EXPECT_LT(matched.median, odometry.median / 2);
  EXPECT_LT(matched.p90, odometry.p90 / 2);
  for (std::size_t i = 0; i < fe.scans.size(); ++i) {  // scans are carried over, only their pose changes
    EXPECT_EQ(fe.scans[i].timestamp, log.raw[i].timestamp);
    EXPECT_EQ(fe.scans[i].points_laser.size(), log.raw[i].points_laser.size());
  }
}

TEST(FrontEnd, SameAnswerEveryRun) {
  const RawLog log = simulated_raw_log(1.0);
  const Scans part(log.raw.begin(), log.raw.begin() + 200);
  const FrontEndResult a = scan_match_log(part), b = scan_match_log(part);
  for (std::size_t i = 0; i < part.size(); ++i) {
    EXPECT_EQ(a.scans[i].T_world_laser.x, b.scans[i].T_world_laser.x);
    EXPECT_EQ(a.scans[i].T_world_laser.theta, b.scans[i].T_world_laser.theta);
  }
}

TEST(FrontEnd, DropsScansWhoseTimeGoesBackwards) {
  const RawLog log = simulated_raw_log(1.0);
  Scans raw(log.raw.begin(), log.raw.begin() + 100);
  raw[50].timestamp = raw[10].timestamp;
  raw[51].timestamp = raw[10].timestamp;
  const FrontEndResult fe = scan_match_log(raw);
  EXPECT_EQ(fe.stats.time_reversals, 2u);
  EXPECT_EQ(fe.scans.size(), 98u);
}

TEST(FrontEnd, WorksWithoutOdometry) {
  const RawLog log = simulated_raw_log(1.0);
  Scans raw(log.raw.begin(), log.raw.begin() + 300);
  for (Scan& s : raw) s.T_world_odom = s.T_world_laser = Pose2{};
  const FrontEndResult fe = scan_match_log(raw);
  EXPECT_FALSE(fe.stats.odometry_moves);
  const Scans truth(log.truth.begin(), log.truth.begin() + 300);
  const Consistency matched = local_consistency(fe.scans, truth, testing::identity_index(raw.size()));
  EXPECT_LT(matched.median, 0.03);  // the robot moves <= 0.1 m per scan: inside the search window
}

// A 60 m ring of long bare corridors (rooms 10-12 m wide, no clutter), and its relations: every tenth scan against
// the one ~10 m further on.
struct CorridorRing {
  Scans truth;
  Relations relations;
};
CorridorRing bare_corridor_ring() {
  SimulatorConfig config;
  config.building.width = 60, config.building.height = 24;
  config.building.min_room_width = 10, config.building.max_room_width = 12;
  config.building.corridor_clutter = 0, config.building.clutter_per_room = 0;
  config.route.laps = 1, config.route.room_visits = 0;
  CorridorRing ring{simulate(config).scans, {}};
  const Scans& truth = ring.truth;
  for (std::size_t i = 0; i + 100 < truth.size(); i += 10)
    ring.relations.push_back({truth[i].timestamp, truth[i + 100].timestamp,
                              truth[i].T_world_laser.inverse() * truth[i + 100].T_world_laser});
  return ring;
}

// Along a bare corridor the walls say nothing about the travel, and the match slides; the odometry's travel is
// kept along the corridor's axis instead.
TEST(FrontEnd, KeepsTheOdometryAlongABareCorridor) {
  const auto [truth, relations] = bare_corridor_ring();
  Scans raw = truth;
  for (Scan& s : raw) s.T_world_laser = s.T_world_odom;
  FrontEndConfig off;
  off.degenerate_ratio = 0;
  const FrontEndResult with = scan_match_log(raw), without = scan_match_log(raw, off);
  const double e_with = relations_error(with.scans, relations).translation_mean;
  const double e_without = relations_error(without.scans, relations).translation_mean;
  EXPECT_GT(with.stats.degenerate, with.scans.size() / 10);
  EXPECT_EQ(without.stats.degenerate, 0u);
  EXPECT_LT(e_with, 0.1) << e_with;
  EXPECT_LT(e_with, e_without / 2) << e_with << " vs " << e_without;
}

// The same ring driven on wheels 5 % short: the odometry's travel is 0.95 times the truth's. Along the bare
// corridors nothing in the scans measures the travel, but the corners between them fix both directions, and there
// the matches measure the odometry's scale (1 / 0.95); the corridors' travel is the odometry's times that scale.
// With the scale right, the learned one stays near 1.
TEST(FrontEnd, LearnsTheOdometrysScaleWhereTheScansFixBothDirections) {
  const auto [truth, relations] = bare_corridor_ring();
  auto scaled_odometry = [&truth](double scale) {
    Scans raw = truth;
    for (std::size_t i = 1; i < raw.size(); ++i) {
      const Pose2 d = truth[i - 1].T_world_laser.inverse() * truth[i].T_world_laser;
      raw[i].T_world_odom = raw[i - 1].T_world_odom * Pose2{scale * d.x, scale * d.y, d.theta};
    }
    for (Scan& s : raw) s.T_world_laser = s.T_world_odom;
    return raw;
  };
  const Scans short_wheels = scaled_odometry(0.95);
  FrontEndConfig off;
  off.scale_memory = 0;
  const FrontEndResult with = scan_match_log(short_wheels), without = scan_match_log(short_wheels, off);
  EXPECT_NEAR(with.stats.odometry_scale, 1 / 0.95, 0.01);
  EXPECT_GT(with.stats.scaled, with.stats.degenerate / 2);
  EXPECT_EQ(without.stats.scaled, 0u);
  EXPECT_EQ(without.stats.odometry_scale, 1.0);
  const double e_with = relations_error(with.scans, relations).translation_mean;
  const double e_without = relations_error(without.scans, relations).translation_mean;
  EXPECT_LT(e_with, e_without / 2) << e_with << " vs " << e_without;
  EXPECT_NEAR(scan_match_log(scaled_odometry(1.0)).stats.odometry_scale, 1.0, 0.005);
}

// The same ring with odometry that is right: where a scan fixes the corridor's axis only weakly (a room's door
// frames, a corner ahead: share of the normals between degenerate_ratio and half_constrained_ratio), the match may
// still slide along it; bounded by what the odometry got wrong on the scans that fix both directions (here next to
// nothing), it keeps the odometry's travel there.
TEST(FrontEnd, BoundsTheMoveAlongAHalfConstrainedCorridorByTheOdometrysRecentError) {
  const auto [truth, relations] = bare_corridor_ring();
  Scans raw = truth;
  for (Scan& s : raw) s.T_world_odom = s.T_world_laser;
  FrontEndConfig on;  // off by default (docs/NOTES.md, "Real logs degraded")
  on.half_constrained_ratio = 0.3;
  const FrontEndResult with = scan_match_log(raw, on), without = scan_match_log(raw);
  const double e_with = relations_error(with.scans, relations).translation_mean;
  const double e_without = relations_error(without.scans, relations).translation_mean;
  EXPECT_GT(with.stats.half_constrained, with.scans.size() / 20);
  EXPECT_EQ(without.stats.half_constrained, 0u);
  EXPECT_LT(e_with, 0.8 * e_without) << e_with << " vs " << e_without;
}

// The jump detector: the odometry slips 0.15 rad at one scan (a wheel on a threshold); the scans say otherwise,
// the front end follows them, and that scan is reported. The clean log has no jump.
TEST(FrontEnd, ReportsATurnThatDisagreesWithTheOdometry) {
  const RawLog log = simulated_raw_log(1.0);
  Scans raw(log.raw.begin(), log.raw.begin() + 300);
  EXPECT_EQ(scan_match_log(raw).stats.heading_jumps, 0u);
  const Pose2 slip{0.0, 0.0, 0.15};
  for (std::size_t i = 150; i < raw.size(); ++i) raw[i].T_world_odom = raw[149].T_world_odom * slip *
                                                                      (raw[149].T_world_odom.inverse() * raw[i].T_world_odom);
  for (Scan& s : raw) s.T_world_laser = s.T_world_odom;
  const FrontEndResult fe = scan_match_log(raw);
  EXPECT_EQ(fe.stats.heading_jumps, 1u);
  ASSERT_FALSE(fe.stats.jump_scans.empty());
  EXPECT_EQ(fe.stats.jump_scans.front(), 150u);
}

// Odometry that stalls and catches up, as MIT CSAIL's raw log does: the pose stands still for 15 scans while the
// robot drives on (more than 1 m), then one increment carries all of it, far past the search window; the front
// end's own velocity predicts the scan, and it is matched from that prediction too.
TEST(FrontEnd, FollowsOdometryThatStallsAndCatchesUp) {
  const RawLog log = simulated_raw_log(1.0);
  Scans raw(log.raw.begin(), log.raw.begin() + 400);
  const Scans truth(log.truth.begin(), log.truth.begin() + 400);
  // Stalls of 15 scans every 60, each where the robot moves more than 1 m over them.
  std::size_t stalls = 0;
  for (std::size_t i = 50; i + 16 < raw.size(); i += 60) {
    if ((truth[i + 15].T_world_laser.translation() - truth[i].T_world_laser.translation()).norm() < 1.0) continue;
    for (std::size_t k = 1; k <= 15; ++k) raw[i + k].T_world_odom = raw[i].T_world_odom;
    ++stalls;
  }
  ASSERT_GE(stalls, 3u);
  for (Scan& s : raw) s.T_world_laser = s.T_world_odom;
  FrontEndConfig off;
  off.second_prediction = 0;
  off.wide_score = 0;  // the wide search would find these scans too
  const FrontEndResult with = scan_match_log(raw), without = scan_match_log(raw, off);
  const auto index = testing::identity_index(raw.size());
  const Consistency c_with = local_consistency(with.scans, truth, index);
  const Consistency c_without = local_consistency(without.scans, truth, index);
  EXPECT_GT(c_without.max, 0.5) << c_without.max;  // the premise: the stalls break the front end without it
  EXPECT_LT(c_with.max, 0.15) << c_with.max;
  EXPECT_GE(with.stats.velocity_kept, 1u);
  EXPECT_LE(with.stats.velocity_kept, stalls);
  EXPECT_EQ(without.stats.second_predictions, 0u);
  // A log whose odometry never stalls hardly needs it: the same answer as without on most scans.
  const FrontEndResult clean = scan_match_log(Scans(log.raw.begin(), log.raw.begin() + 400));
  EXPECT_LT(clean.stats.velocity_kept, 40u);
}

// A heading lost between two scans (aces's ROS bag: its odometry stamped out of step with the scans, a gap of 3 s
// in the log, the odometry's turn 0.84 rad off at one scan): from scan 150 on the odometry is turned by 1 rad, far
// outside the search window. The match from the prediction scores poorly, the scan is matched again over every
// heading, and the front end stays right; without it the rest of the log is turned. (The constant-velocity
// prediction, off here, catches such a slip on a steady stretch; after aces's gap it predicted no better.)
TEST(FrontEnd, FindsAHeadingLostBetweenTwoScans) {
  const RawLog log = simulated_raw_log(1.0);
  Scans raw(log.raw.begin(), log.raw.begin() + 300);
  const Scans truth(log.truth.begin(), log.truth.begin() + 300);
  const Pose2 slip{0.0, 0.0, 1.0};
  for (std::size_t i = 150; i < raw.size(); ++i)
    raw[i].T_world_odom = raw[149].T_world_odom * slip * (raw[149].T_world_odom.inverse() * raw[i].T_world_odom);
  for (Scan& s : raw) s.T_world_laser = s.T_world_odom;
  FrontEndConfig on, off;
  on.second_prediction = off.second_prediction = 0;
  off.wide_score = 0;
  const FrontEndResult with = scan_match_log(raw, on), without = scan_match_log(raw, off);
  const auto index = testing::identity_index(raw.size());
  const Consistency c_with = local_consistency(with.scans, truth, index);
  const Consistency c_without = local_consistency(without.scans, truth, index);
  EXPECT_GT(c_without.max, 0.5) << c_without.max;  // the premise: the lost heading breaks the front end without it
  EXPECT_LT(c_with.max, 0.15) << c_with.max;
  EXPECT_GE(with.stats.wide_kept, 1u);
  EXPECT_EQ(without.stats.wide_searches, 0u);
  // Without the wide search the chain rests on poor fits after the slip, and the stats say where the worst is.
  EXPECT_GE(without.stats.weak_matches, 1u);
  EXPECT_LT(without.stats.weakest_score, kWeakMatch);
  EXPECT_GE(without.stats.weakest_scan, 150u);
  EXPECT_GT(with.stats.weakest_score, without.stats.weakest_score);
  // The clean log's matches all score well: nothing searched again.
  EXPECT_EQ(scan_match_log(Scans(log.raw.begin(), log.raw.begin() + 300)).stats.wide_searches, 0u);
}

// A laser mounted upside down and read as upright (a bag without its mount's transform, a log that stores the
// beams left to right): every scan is the mirror image of the room. The front end follows the scans and turns
// against the wheels; with the mirror check it notices and matches the scans mirrored back.
TEST(FrontEnd, MatchesTheScansOfALaserMountedUpsideDownMirroredBack) {
  const RawLog log = simulated_raw_log(1.0);
  const Scans raw(log.raw.begin(), log.raw.begin() + 400), truth(log.truth.begin(), log.truth.begin() + 400);
  Scans upside_down = raw;
  for (Scan& s : upside_down)
    for (Vec2& p : s.points_laser) p.y() = -p.y();
  FrontEndConfig off;
  off.mirror_check = false;
  const FrontEndResult upright = scan_match_log(raw), as_read = scan_match_log(upside_down, off),
                       checked = scan_match_log(upside_down);
  EXPECT_FALSE(upright.stats.mirrored);
  EXPECT_GE(upright.stats.turning_steps, kMinTurningSteps);
  EXPECT_GT(upright.stats.turn_slope(), 0.8);
  EXPECT_TRUE(mirrored_description(upright.stats).empty());
  EXPECT_FALSE(as_read.stats.mirrored);
  EXPECT_TRUE(as_read.stats.turns_against_odometry());
  EXPECT_LT(as_read.stats.turn_slope(), -0.5);
  ASSERT_TRUE(checked.stats.mirrored);
  EXPECT_FALSE(checked.stats.turns_against_odometry());
  EXPECT_GT(checked.stats.turn_slope(), 0.8);
  EXPECT_NEAR(checked.stats.unmirrored_turn_slope, as_read.stats.turn_slope(), 1e-12);
  EXPECT_NE(mirrored_description(checked.stats).find("read mirrored"), std::string::npos);
  ASSERT_EQ(checked.scans.size(), raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) {  // the points mirrored back are the upright laser's
    ASSERT_EQ(checked.scans[i].points_laser.size(), raw[i].points_laser.size());
    for (std::size_t k = 0; k < raw[i].points_laser.size(); ++k)
      EXPECT_EQ(checked.scans[i].points_laser[k], raw[i].points_laser[k]);
  }
  const auto index = testing::identity_index(raw.size());
  EXPECT_LT(local_consistency(checked.scans, truth, index).median, 0.03);
}

TEST(FrontEnd, RefusesAbsurdConfigs) {
  FrontEndConfig c;
  c.local_map_scans = 0;
  EXPECT_THROW(scan_match_log({}, c), InputError);
  c = {};
  c.max_range = -1;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.min_score = 2;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.degenerate_ratio = 1;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.matcher.sigma = 0;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.second_prediction = -0.1;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.half_constrained_ratio = 1;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.half_constrained_slack = std::nan("");
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.scale_memory = -1;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.scale_ratio = 1;
  EXPECT_THROW(validate(c), InputError);
  EXPECT_EQ(scan_match_log({}).scans.size(), 0u);
}

}  // namespace
}  // namespace partslam
