#include "core/evaluation/tracking.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/maps/occupancy_grid.h"

namespace partslam {
namespace {

// One local map of the run: its true pose, overlap, and its frame in the twin's odometry frame.
struct LocalMap {
  bool ok = false;
  Submap map;
  Pose2 T_odom_map;
  double overlap = 0;
};

}  // namespace

TrackingReport evaluate_tracking(const GridMap& map, const Scans& scans, std::size_t first,
                                 const TrackingBenchConfig& config) {
  validate(config.tracker);
  if (first >= scans.size()) throw InputError("tracking: no scan after the map's last one");
  const Localizer localizer(map, config.localizer);
  const DmmConfig& dmm = config.localizer.dmm;
  const OccupancyGrid seen = build_occupancy_grid(occupied_points(map), dmm.resolution, dmm.dilation);
  const Scans twin = drifted_twin(scans, odometry_noise(config.noise), config.seed);
  const std::vector<double> travel = travel_distances(scans);
  const double window = config.submap.window_length;
  const auto local_map = [&](double s) {
    LocalMap m;
    try {
      m.map = build_local_map(scans, s, s + window, config.submap);
    } catch (const InputError&) {
      return m;  // too few points (a turn on the spot, a blank wall)
    }
    const std::size_t a = static_cast<std::size_t>(m.map.anchor_scan);
    m.T_odom_map = twin[a].T_world_laser * scans[a].T_world_laser.inverse() * m.map.T_world_map;
    m.overlap = static_cast<double>(count_inliers(m.map.points, seen, m.map.T_world_map)) /
                static_cast<double>(m.map.points.size());
    m.ok = true;
    return m;
  };
  std::vector<double> starts;
  for (double s = travel[first]; s + config.run_length + window <= travel.back(); s += config.start_spacing)
    starts.push_back(s);
  if (starts.empty()) throw InputError("tracking: the log after the map is shorter than one run");
  if (starts.size() > static_cast<std::size_t>(config.max_starts)) {
    std::vector<double> spread;
    for (int k = 0; k < config.max_starts; ++k)
      spread.push_back(starts[static_cast<std::size_t>(k) * starts.size() / static_cast<std::size_t>(config.max_starts)]);
    starts = spread;
  }
  // The starts whose first converge_within of local maps are all in the map: a kidnapping jumps to one.
  std::vector<bool> in_map(starts.size(), true);
  for (std::size_t k = 0; k < starts.size(); ++k)
    for (double s = starts[k]; s - starts[k] < config.converge_within && in_map[k]; s += config.step) {
      const LocalMap m = local_map(s);
      in_map[k] = m.ok && m.overlap >= config.min_overlap;
    }
  TrackingReport report;
  std::vector<double> times;
  Tracker tracker(localizer, config.tracker);
  for (std::size_t k = 0; k < starts.size(); ++k) {
    TrackingRun run;
    run.start = starts[k];
    // The first start in the map from half the starts on (another part of the log), else half the starts on.
    run.jump_to = starts[(k + starts.size() / 2) % starts.size()];
    for (std::size_t d = 0; d < starts.size(); ++d) {
      const std::size_t j = (k + starts.size() / 2 + d) % starts.size();
      if (j != k && in_map[j]) {
        run.jump_to = starts[j];
        break;
      }
    }
    tracker.reset();
    Pose2 T_rebase, T_odom_last;
    bool lost = false, first_hypotheses = false;
    for (int half = 0; half < 2; ++half) {
      const double from = half == 0 ? run.start : run.jump_to;
      bool first_of_half = true;
      for (double s = from; s < from + config.run_length; s += config.step) {
        const LocalMap m = local_map(s);
        const double t = (half == 0 ? 0.0 : config.run_length) + (s - from);
        if (half == 1 && s - from < config.recover_within && m.ok && m.overlap >= config.min_overlap)
          run.jump_in_map = true;
        if (!m.ok) continue;
        if (half == 1 && first_of_half) T_rebase = T_odom_last * m.T_odom_map.inverse();  // odometry goes on
        first_of_half = false;
        const Pose2 T_odom_map = half == 1 ? T_rebase * m.T_odom_map : m.T_odom_map;
        T_odom_last = T_odom_map;
        TrackedStep ts;
        ts.travel = t;
        ts.after_jump = half == 1;
        ts.overlap = m.overlap;
        ts.step = tracker.step(m.map.points, m.map.origins, T_odom_map);
        times.push_back(ts.step.time_ms);
        ts.right = ts.step.has_pose && config.correct.accepts(ts.step.best.T_map_query, m.map.T_world_map);
        const Pose2 error = m.map.T_world_map.inverse() * ts.step.best.T_map_query;
        ts.translation_error = std::hypot(error.x, error.y), ts.rotation_error = std::abs(error.theta);
        if (!first_hypotheses && !ts.step.hypotheses.empty()) {  // the first search's (it may end steps later)
          first_hypotheses = true;
          for (const TrackHypothesis& h : ts.step.hypotheses)
            run.truth_among_first = run.truth_among_first || config.correct.accepts(h.T_map_query, m.map.T_world_map);
        }
        if (run.steps.empty()) {
          const Localization single = localizer.locate(m.map.points, m.map.origins);
          run.single_shot_right = is_confident(single) && config.correct.accepts(single.T_map_query, m.map.T_world_map);
        }
        const bool localised = ts.step.status == TrackStatus::kLocalised;
        if (localised && !ts.right) {
          ++run.declared_wrong;
          run.declared_wrong_in_map += m.overlap >= config.min_overlap;
        }
        if (half == 0 && localised && run.converged < 0) run.converged = t, run.converged_right = ts.right;
        if (half == 1 && run.localised_at_jump && !localised && run.noticed < 0) run.noticed = s - from;
        if (half == 1 && ts.step.status == TrackStatus::kLost) lost = true;
        if (half == 1 && lost && localised && ts.right && run.recovered < 0) run.recovered = s - from;
        run.steps.push_back(ts);
      }
      if (half == 0)
        run.localised_at_jump = !run.steps.empty() && run.steps.back().step.status == TrackStatus::kLocalised;
    }
    run.eligible = in_map[k];  // its first converge_within, as the run saw it
    report.runs.push_back(std::move(run));
  }
  report.median_ms = percentile(times, 0.5);
  report.p95_ms = percentile(times, 0.95);
  return report;
}

}  // namespace partslam
