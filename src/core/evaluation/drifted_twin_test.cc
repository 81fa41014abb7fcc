#include "core/evaluation/drifted_twin.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/evaluation/trajectory_check.h"

namespace partslam {
namespace {

// Twice round a 10 m x 4 m rectangle, one scan every 0.1 m, one point per scan.
Scans loop_twice() {
  Scans scans;
  const double side[] = {10, 4, 10, 4};
  Pose2 pose;
  for (int lap = 0; lap < 2; ++lap)
    for (double length : side) {
      for (int k = 0; k < static_cast<int>(std::lround(length / 0.1)); ++k) {
        Scan s;
        s.timestamp = 0.1 * static_cast<double>(scans.size());
        s.T_world_laser = s.T_world_odom = pose;
        s.points_laser = {{1.0, 0.5}};
        scans.push_back(s);
        pose = pose * Pose2{0.1, 0.0, 0.0};
      }
      pose = pose * Pose2{0.0, 0.0, std::acos(-1.0) / 2};
    }
  return scans;
}

TEST(DriftedTwin, WithoutNoiseIsTheTruthAndKeepsTheScans) {
  const Scans truth = loop_twice();
  const Scans twin = drifted_twin(truth, {}, 1);
  ASSERT_EQ(twin.size(), truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_NEAR((twin[i].T_world_laser.translation() - truth[i].T_world_laser.translation()).norm(), 0.0, 1e-9);
    EXPECT_EQ(twin[i].T_world_odom.x, twin[i].T_world_laser.x);
    EXPECT_EQ(twin[i].points_laser, truth[i].points_laser);
    EXPECT_EQ(twin[i].timestamp, truth[i].timestamp);
  }
}

TEST(DriftedTwin, DriftsDeterministicallyGivenTheSeedAndMoreWhenHarsh) {
  const Scans truth = loop_twice();
  const Relations relations = bench_relations(truth);
  const auto error = [&](const std::string& level, std::uint64_t seed) {
    return relations_error(drifted_twin(truth, odometry_noise(level), seed), relations).translation_mean;
  };
  EXPECT_EQ(error("mild", 3), error("mild", 3));
  EXPECT_NE(error("mild", 3), error("mild", 4));
  double mild = 0, harsh = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) mild += error("mild", seed), harsh += error("harsh", seed);
  EXPECT_GT(mild, 0.0);
  EXPECT_GT(harsh, 3 * mild);
}

TEST(DriftedTwin, RefusesAnUnknownLevelAndNegativeNoise) {
  EXPECT_THROW(odometry_noise("medium"), InputError);
  OdometryNoise n;
  n.rotation_noise = -1;
  try {
    drifted_twin(loop_twice(), n, 1);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rotation_noise"), std::string::npos);
  }
}

TEST(BenchRelations, PairTravelOffsetsAndRevisitsOfTheTruth) {
  const Scans truth = loop_twice();  // 56 m: a lap is 28 m
  BenchRelationsConfig c;
  c.travel_offsets = {5.0};
  const Relations r = bench_relations(truth, c);
  EXPECT_NEAR(relations_error(truth, r).translation_mean, 0.0, 1e-12);
  EXPECT_EQ(relations_error(truth, r).missing, 0u);
  std::size_t revisits = 0, offsets = 0;
  for (const Relation& x : r) {
    if (x.t2 - x.t1 >= 20.0 * 1.0 - 1e-9) {  // 0.1 s per 0.1 m: travel gap >= 20 m
      ++revisits;
      EXPECT_LE(x.T_1_2.translation().norm(), 1.0);
    } else {
      ++offsets;
      EXPECT_NEAR(x.t2 - x.t1, 5.0, 0.11);
    }
  }
  EXPECT_GT(revisits, 20u);  // the second lap revisits the first
  EXPECT_GT(offsets, 40u);
}

TEST(BenchRelations, NeverNamesAScanThatSharesItsMillisecond) {
  Scans truth = loop_twice();
  truth[11].timestamp = truth[10].timestamp + 5e-4;  // two scans within 1 ms: neither can be named
  BenchRelationsConfig c;
  c.spacing = 0.05;
  for (const Relation& x : bench_relations(truth, c)) {
    EXPECT_GT(std::abs(x.t1 - truth[10].timestamp), 1e-3);
    EXPECT_GT(std::abs(x.t2 - truth[10].timestamp), 1e-3);
  }
  EXPECT_THROW(bench_relations(Scans(truth.begin(), truth.begin() + 3), c), InputError);
}

}  // namespace
}  // namespace partslam
