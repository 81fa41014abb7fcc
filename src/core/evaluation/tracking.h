// The tracking bench (docs/NOTES.md, "Tracking"; `make relocalisation`): the relocalisation protocol's
// building map (the first visit of each place, core/evaluation/relocalisation.h), and runs of the tracker
// (core/matching/tracker.h) that start every start_spacing of travel after it. A run's local maps are built from
// the corrected log (the shapes a scan-matched local map has) and its motion is a drifted twin's odometry
// (core/evaluation/drifted_twin.h), not the corrected poses. Each run tracks run_length of travel, then is
// kidnapped: the log jumps to another start (the first, from half the starts on, whose first converge_within is
// in the map; its odometry goes on as if nothing happened) and tracking goes on for run_length more. Truth: the
// corrected poses.
#pragma once

#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "core/evaluation/drifted_twin.h"
#include "core/evaluation/relocalisation.h"
#include "core/matching/tracker.h"

namespace partslam {

struct TrackingBenchConfig {
  double step = 2.0;             ///< travel between consecutive local maps [m]
  double start_spacing = 10.0;   ///< travel between the starts of runs [m]
  int max_starts = 40;           ///< at most this many starts per log, evenly spread
  double run_length = 40.0;      ///< travel tracked before the kidnapping, and after it [m]
  double converge_within = 20.0; ///< a start counts when it stays in the map this long [m] ...
  double recover_within = 30.0;  ///< ... and a kidnapping is recovered within this travel [m]
  double min_overlap = 0.3;      ///< a local map is in the map at this true overlap
  PoseTolerance correct{0.3, 3.0 * std::numbers::pi / 180};
  std::string noise = "mild";    ///< the drifted twin's level (odometry_noise)
  std::uint64_t seed = 1;
  SubmapConfig submap;
  LocalizerConfig localizer;
  TrackerConfig tracker;
};

struct TrackedStep {
  double travel = 0;      ///< since the run's start (the kidnapped half goes on counting) [m]
  bool after_jump = false;
  double overlap = 0;     ///< true overlap with the building map
  TrackStep step;
  bool right = false;     ///< step.best within `correct` of the truth (has_pose)
  double translation_error = 0, rotation_error = 0;  ///< step.best's from the truth [m], [rad]
};

struct TrackingRun {
  double start = 0, jump_to = 0;  ///< travel along the log of the two halves' first local maps [m]
  std::vector<TrackedStep> steps;
  bool eligible = false;     ///< every local map of its first converge_within is in the map
  double converged = -1;     ///< travel to its first localised step (before the jump), -1: never [m]
  bool converged_right = false;
  bool truth_among_first = false;  ///< the first step with hypotheses held the true pose among them
  bool single_shot_right = false;  ///< locate() on the first local map alone: confident and right
  bool localised_at_jump = false;  ///< localised on the last step before the jump
  bool jump_in_map = false;  ///< some local map of the jump's first recover_within is in the map
  double noticed = -1;       ///< travel after the jump to the first step not localised, -1: never [m]
  double recovered = -1;     ///< travel after the jump to the first right localised step after a "lost" [m]
  int declared_wrong = 0;    ///< localised steps whose pose is wrong
  int declared_wrong_in_map = 0;  ///< ... of them in the map
};

struct TrackingReport {
  std::vector<TrackingRun> runs;
  double median_ms = 0, p95_ms = 0;  ///< time per step (one core)
};

/// Runs the bench on a corrected log whose scans [0, first) built `map`. Throws InputError when no run can start.
TrackingReport evaluate_tracking(const GridMap& map, const Scans& scans, std::size_t first,
                                 const TrackingBenchConfig& config = {});

}  // namespace partslam
