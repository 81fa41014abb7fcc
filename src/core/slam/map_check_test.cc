#include "core/slam/map_check.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/sim/simulator.h"

namespace partslam {
namespace {

// Two laps of a simulated building, exact poses: every place is seen on both laps.
Scans two_lap_scans() {
  SimulatorConfig config;
  config.route.laps = 2;
  config.route.room_visits = 1;
  return simulate(config).scans;
}

TEST(MapCheck, ARightMapPassesAndAMapWithAWingDrawnTwiceFails) {
  const Scans truth = two_lap_scans();
  const MapCheck right = check_map(truth);
  EXPECT_TRUE(right.judged);
  EXPECT_GT(right.revisiting_beams, right.beams / 10);  // the second lap sees the first lap's walls
  EXPECT_LT(right.crossing_share, 0.02) << right.crossing_share;
  EXPECT_TRUE(right.passed);
  // The second lap turned by 5 degrees about the start and shifted by 1 m: its beams cross the first lap's walls.
  Scans wrong = truth;
  const Pose2 error{1.0, 0.5, 5.0 * 3.14159265358979 / 180.0};
  for (std::size_t i = wrong.size() / 2; i < wrong.size(); ++i) wrong[i].T_world_laser = error * wrong[i].T_world_laser;
  const MapCheck bad = check_map(wrong);
  EXPECT_TRUE(bad.judged);
  EXPECT_GT(bad.crossing_share, 5 * right.crossing_share);
  EXPECT_FALSE(bad.passed) << bad.crossing_share;
  EXPECT_GT(bad.worst_place_crossings, 0u);
}

TEST(MapCheck, ALogThatNeverComesBackIsNotJudged) {
  const Scans truth = two_lap_scans();
  const Scans first_lap(truth.begin(), truth.begin() + static_cast<std::ptrdiff_t>(truth.size() / 4));
  const MapCheck m = check_map(first_lap);
  EXPECT_GT(m.beams, 0u);
  EXPECT_FALSE(m.judged);
  EXPECT_TRUE(m.passed);
  EXPECT_EQ(check_map({}).beams, 0u);
}

TEST(MapCheck, SameAnswerEveryRun) {
  const Scans truth = two_lap_scans();
  const MapCheck a = check_map(truth), b = check_map(truth);
  EXPECT_EQ(a.crossing_beams, b.crossing_beams);
  EXPECT_EQ(a.revisiting_beams, b.revisiting_beams);
}

TEST(MapCheck, RefusesAbsurdConfigs) {
  MapCheckConfig c;
  c.resolution = 0;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.max_crossing_share = 2;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.min_hits = 0;
  EXPECT_THROW(check_map({}, c), InputError);
}

}  // namespace
}  // namespace partslam
