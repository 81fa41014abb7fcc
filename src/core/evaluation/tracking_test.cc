#include "core/evaluation/tracking.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/maps/grid_map.h"
#include "core/sim/simulator.h"

namespace partslam {
namespace {

// The bench on the simulated building, mapped from its whole log (so every local map is in the map): runs
// start, get localised, are kidnapped to another start, notice it and localise again; no step is declared at
// a wrong pose, and the figures are what the steps say.
TEST(TrackingBench, RunsAreLocalisedKidnappedAndLocalisedAgainOnTheSimulator) {
  const Scans scans = simulate(SimulatorConfig{}).scans;
  TrackingBenchConfig config;
  config.max_starts = 3;
  config.run_length = 16;
  config.converge_within = 10;
  config.recover_within = 16;
  config.start_spacing = 30;
  const TrackingReport r = evaluate_tracking(build_grid_map(scans), scans, 0, config);
  ASSERT_EQ(r.runs.size(), 3u);
  for (const TrackingRun& run : r.runs) {
    EXPECT_NE(run.start, run.jump_to);
    EXPECT_GE(run.steps.size(), 12u);
    EXPECT_TRUE(run.eligible);
    EXPECT_GE(run.converged, 0.0);
    EXPECT_TRUE(run.converged_right);
    EXPECT_TRUE(run.truth_among_first);
    EXPECT_EQ(run.declared_wrong, 0);
    int wrong = 0;
    for (const TrackedStep& s : run.steps) {
      wrong += s.step.status == TrackStatus::kLocalised && !s.right;
      EXPECT_EQ(s.right, s.step.has_pose && s.translation_error <= config.correct.translation &&
                             s.rotation_error <= config.correct.rotation);
    }
    EXPECT_EQ(wrong, run.declared_wrong);
    if (run.localised_at_jump) {
      EXPECT_GE(run.noticed, 0.0);
      EXPECT_GE(run.recovered, run.noticed);
    }
  }
  EXPECT_GT(r.p95_ms, 0.0);
  EXPECT_GE(r.p95_ms, r.median_ms);
  EXPECT_THROW(evaluate_tracking(build_grid_map(scans), scans, scans.size(), config), InputError);
}

}  // namespace
}  // namespace partslam
