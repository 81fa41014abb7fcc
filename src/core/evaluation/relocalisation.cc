#include "core/evaluation/relocalisation.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/maps/occupancy_grid.h"

namespace partslam {
double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::floor(q * static_cast<double>(v.size() - 1) + 0.5))];
}

std::size_t first_revisit(const Scans& scans, double revisit_radius, double revisit_gap) {
  const std::vector<double> travel = travel_distances(scans);
  std::size_t earliest = 0;  // scans [0, earliest) are at least revisit_gap of travel behind scan i
  for (std::size_t i = 0; i < scans.size(); ++i) {
    while (earliest < i && travel[i] - travel[earliest] >= revisit_gap) ++earliest;
    const Vec2 p = scans[i].T_world_laser.translation();
    for (std::size_t j = 0; j < earliest; ++j) {
      if ((scans[j].T_world_laser.translation() - p).norm() <= revisit_radius) return i;
    }
  }
  return scans.size();
}

RelocalisationReport evaluate_relocalisation(const GridMap& map, const Scans& scans, std::size_t first_query,
                                             const RelocalisationConfig& config) {
  const Points2 map_points = occupied_points(map);
  const Localizer localizer(map, config.localizer);
  const DmmConfig& dmm = config.localizer.dmm;
  const OccupancyGrid seen = build_occupancy_grid(map_points, dmm.resolution, dmm.dilation);
  const std::vector<double> travel = travel_distances(scans);
  RelocalisationReport report;
  report.wing_directions = localizer.wing_directions();
  std::vector<double> times;
  if (first_query >= scans.size()) throw InputError("relocalisation: no scan after the map's last one");
  for (double s = travel[first_query]; s + config.submap.window_length <= travel.back(); s += config.query_spacing) {
    Submap query;
    try {
      query = build_local_map(scans, s, s + config.submap.window_length, config.submap);
    } catch (const InputError&) {
      continue;  // too few points in this window (the robot turned on the spot, a blank wall)
    }
    RelocalisationOutcome o;
    o.travel = s;
    o.truth = query.T_world_map;
    o.overlap = static_cast<double>(count_inliers(query.points, seen, o.truth)) / query.points.size();
    o.result = localizer.locate(query.points, query.origins);
    o.truth_score = localizer.score_at(query.points, o.truth);
    o.truth_verified = localizer.verify(query.points, query.origins, o.truth);
    const Pose2 error = o.truth.inverse() * o.result.T_map_query;
    o.translation_error = std::hypot(error.x, error.y);
    o.rotation_error = std::abs(error.theta);
    o.correct = config.correct.accepts(o.truth, o.result.T_map_query);
    const bool in_map = o.overlap >= config.min_overlap;
    const bool confident = is_confident(o.result, config.confident_rule);
    report.in_map += in_map;
    report.in_map_correct += in_map && o.correct;
    report.confident += confident;
    report.confident_wrong += confident && !o.correct;
    report.outside += !in_map;
    report.outside_confident += !in_map && confident;
    times.push_back(o.result.time_ms);
    report.outcomes.push_back(o);
  }
  if (report.outcomes.empty()) throw InputError("relocalisation: no local map could be built after the map's scans");
  report.median_ms = percentile(times, 0.5);
  report.p95_ms = percentile(times, 0.95);
  return report;
}

}  // namespace partslam
