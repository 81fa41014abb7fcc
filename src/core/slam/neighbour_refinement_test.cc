#include "core/slam/neighbour_refinement.h"

#include <gtest/gtest.h>

#include <random>

#include "core/error.h"
#include "core/sim/simulator.h"

namespace partslam {
namespace {

// The simulator's first scans at their exact poses, and the same scans with every pose jittered by a few
// centimetres and a fraction of a degree (a front end's matches).
struct Jittered {
  Scans truth, jittered;
};

Jittered jittered_scans(std::size_t count) {
  Jittered j;
  j.truth = simulate(SimulatorConfig{}).scans;
  j.truth.resize(std::min(count, j.truth.size()));
  j.jittered = j.truth;
  std::mt19937 random(7);
  std::normal_distribution<double> metres(0.0, 0.02), radians(0.0, 0.005);
  for (Scan& s : j.jittered)
    s.T_world_laser = Pose2{s.T_world_laser.x + metres(random), s.T_world_laser.y + metres(random),
                            wrap_angle(s.T_world_laser.theta + radians(random))};
  return j;
}

double mean_error(const Scans& a, const Scans& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i].T_world_laser.translation() - b[i].T_world_laser.translation()).norm();
  return sum / static_cast<double>(a.size());
}

TEST(NeighbourRefinement, BringsJitteredScansCloserToTheirPoses) {
  const Jittered j = jittered_scans(400);
  NeighbourRefinementStats stats;
  const Scans refined = refine_on_neighbours(j.jittered, {}, {}, &stats);
  ASSERT_EQ(refined.size(), j.jittered.size());
  const double before = mean_error(j.jittered, j.truth), after = mean_error(refined, j.truth);
  EXPECT_LT(after, 0.7 * before) << before << " -> " << after;
  EXPECT_GT(stats.refined, j.truth.size());  // two rounds, nearly every scan each time
  EXPECT_GT(stats.mean_move, 0.0);
  EXPECT_LT(stats.mean_move, 0.1);
  for (std::size_t i = 0; i < refined.size(); ++i) {  // only the poses change
    EXPECT_EQ(refined[i].timestamp, j.jittered[i].timestamp);
    EXPECT_EQ(refined[i].points_laser.size(), j.jittered[i].points_laser.size());
  }
}

TEST(NeighbourRefinement, TheAnswerDoesNotDependOnTheThreads) {
  const Jittered j = jittered_scans(200);
  NeighbourRefinementConfig one, three;
  three.num_threads = 3;
  const Scans a = refine_on_neighbours(j.jittered, one, {}), b = refine_on_neighbours(j.jittered, three, {});
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].T_world_laser.x, b[i].T_world_laser.x) << i;
    EXPECT_EQ(a[i].T_world_laser.y, b[i].T_world_laser.y) << i;
    EXPECT_EQ(a[i].T_world_laser.theta, b[i].T_world_laser.theta) << i;
  }
}

// A scan put half a metre off is not pulled back from there: a move beyond max_move is not taken (counted).
TEST(NeighbourRefinement, AMoveBeyondTheBoundIsNotTaken) {
  Jittered j = jittered_scans(200);
  Scans scans = j.truth;
  scans[100].T_world_laser.x += 0.5;
  NeighbourRefinementConfig c;
  c.rounds = 1;
  NeighbourRefinementStats stats;
  const Scans refined = refine_on_neighbours(scans, c, {}, &stats);
  EXPECT_LE((refined[100].T_world_laser.translation() - scans[100].T_world_laser.translation()).norm(), c.max_move);
  c.max_move = 0.01;
  const Scans held = refine_on_neighbours(j.jittered, c, {}, &stats);
  EXPECT_GT(stats.too_far, 10u);
  for (std::size_t i = 0; i < held.size(); ++i)
    EXPECT_LE((held[i].T_world_laser.translation() - j.jittered[i].T_world_laser.translation()).norm(), 0.01 + 1e-12);
}

TEST(NeighbourRefinement, NoRoundsLeavesTheScansAndBadSettingsAreNamed) {
  const Jittered j = jittered_scans(50);
  NeighbourRefinementConfig off;
  off.rounds = 0;
  const Scans same = refine_on_neighbours(j.jittered, off, {});
  for (std::size_t i = 0; i < same.size(); ++i) EXPECT_EQ(same[i].T_world_laser.x, j.jittered[i].T_world_laser.x);
  for (const auto& [field, set] : std::vector<std::pair<std::string, void (*)(NeighbourRefinementConfig&)>>{
           {"rounds", [](NeighbourRefinementConfig& c) { c.rounds = -1; }},
           {"window", [](NeighbourRefinementConfig& c) { c.window = 0; }},
           {"block", [](NeighbourRefinementConfig& c) { c.block = 0; }},
           {"sigma", [](NeighbourRefinementConfig& c) { c.sigma = std::numeric_limits<double>::quiet_NaN(); }},
           {"max_move", [](NeighbourRefinementConfig& c) { c.max_move = 0; }},
           {"num_threads", [](NeighbourRefinementConfig& c) { c.num_threads = 0; }}}) {
    NeighbourRefinementConfig c;
    set(c);
    try {
      validate(c);
      ADD_FAILURE() << field << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace partslam
