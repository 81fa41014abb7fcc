#include "io/logs/ground_truth.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "core/sim/simulator.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

// A raw log of the simulator (odometry in the pose slots) and relations written from its exact poses: the
// reference solved from them must give the exact relative poses back, also between scans far apart.
TEST(GroundTruth, RelationsGiveAReferenceTrajectory) {
  testing::TempDir dir;
  SimulatorConfig sim;
  sim.route.laps = 1;
  const Scans truth = simulate(sim).scans;
  Scans raw = truth;
  for (Scan& s : raw) s.T_world_laser = s.T_world_odom;
  {
    std::ofstream out(dir / "sim.relations");
    out.precision(12);
    for (std::size_t i = 0; i + 10 < truth.size(); i += 10) {  // a chain of short relations
      const Pose2 T = truth[i].T_world_laser.inverse() * truth[i + 10].T_world_laser;
      out << truth[i].timestamp << " " << truth[i + 10].timestamp << " " << T.x << " " << T.y << " 0 0 0 " << T.theta
          << "\n";
    }
  }
  const GroundTruth g = load_ground_truth((dir / "sim.relations").string(), raw);
  EXPECT_THAT(g.description, ::testing::HasSubstr("relations"));
  std::size_t first = 0, last = 0, known = 0;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (!g.index[i]) continue;
    if (known++ == 0) first = i;
    last = i;
  }
  ASSERT_GT(known, 100u);
  const Pose2 ref = g.reference[*g.index[first]].T_world_laser.inverse() * g.reference[*g.index[last]].T_world_laser;
  const Pose2 exact = truth[first].T_world_laser.inverse() * truth[last].T_world_laser;
  const Pose2 odometry = raw[first].T_world_laser.inverse() * raw[last].T_world_laser;
  EXPECT_LT((ref.translation() - exact.translation()).norm(), 0.05);
  EXPECT_GT((odometry.translation() - exact.translation()).norm(), 0.2);  // the premise: odometry drifted

  {
    std::ofstream out(dir / "other.relations");
    out << "1e9 2e9 0 0 0 0 0 0\n";
  }
  EXPECT_THROW(load_ground_truth((dir / "other.relations").string(), raw), InputError);
}

}  // namespace
}  // namespace partslam::io
