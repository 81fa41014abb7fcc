#include "core/slam/closure_refinement.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "core/error.h"
#include "core/matching/scan_matcher.h"
#include "core/parallel.h"

namespace partslam {
namespace {

void require_in(double value, double lo, double hi, bool lo_open, const char* field) {
  if (!std::isfinite(value) || value > hi || (lo_open ? value <= lo : value < lo))
    throw InputError(std::string("closure refinement config: ") + field + " must be in " + (lo_open ? "(" : "[") +
                     std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(value));
}

// The endpoints of the scans whose travel lies in [travel - context, travel + L + context], in the submap's frame,
// one per cell.
Points2 fine_points(const Scans& scans, const std::vector<double>& s, const Submap& m, double window_length,
                    const ClosureRefinementConfig& c) {
  const Pose2 T_map_world = m.T_world_map.inverse();
  const auto lo = std::lower_bound(s.begin(), s.end(), m.travel - c.context) - s.begin();
  const auto hi = std::upper_bound(s.begin(), s.end(), m.travel + window_length + c.context) - s.begin();
  Points2 out;
  for (auto i = lo; i < hi; ++i) {
    const Scan& scan = scans[static_cast<std::size_t>(i)];
    const Pose2 T = T_map_world * scan.T_world_laser;
    for (const Vec2& p : scan.points_laser)
      if (p.squaredNorm() <= c.max_range * c.max_range) out.push_back(T * p);
  }
  return voxel_downsample(out, c.resolution);
}

Points2 thinned(const Points2& points, std::size_t max_points) {
  if (points.size() <= max_points) return points;
  Points2 out;
  const std::size_t stride = (points.size() + max_points - 1) / max_points;
  for (std::size_t i = 0; i < points.size(); i += stride) out.push_back(points[i]);
  return out;
}

}  // namespace

void validate(const ClosureRefinementConfig& c) {
  require_in(c.context, 0, 100, false, "context [m]");
  require_in(c.resolution, 0, 1, true, "resolution [m]");
  require_in(c.sigma, 0, 1, true, "sigma [m]");
  require_in(c.max_range, 0, 1000, true, "max_range [m]");
  require_in(c.linear_window, 0, 1, false, "linear_window [m]");
  require_in(c.angular_window, 0, 0.5, false, "angular_window [rad]");
  if (c.max_points < 10 || c.max_points > 1000000)
    throw InputError("closure refinement config: max_points must be in [10, 1000000], got " +
                     std::to_string(c.max_points));
  if (c.num_threads < 1 || c.num_threads > 1024)
    throw InputError("closure refinement config: num_threads must be in [1, 1024], got " +
                     std::to_string(c.num_threads));
  if (c.linear_window / c.resolution > 200)
    throw InputError("closure refinement config: linear_window spans more than 200 cells of resolution");
}

std::vector<LoopClosure> refine_closures(const Scans& scans, const Submaps& maps, double window_length,
                                         std::vector<LoopClosure> closures, const ClosureRefinementConfig& c) {
  validate(c);
  if (!c.enabled || closures.empty()) return closures;
  for (const LoopClosure& l : closures)
    if (l.query >= maps.size() || l.match >= maps.size())
      throw InputError("closure refinement: a closure names submap " + std::to_string(std::max(l.query, l.match)) +
                       " of " + std::to_string(maps.size()));
  const std::vector<double> s = travel_distances(scans);
  // The closures of each match (one likelihood field each), and the query sides' thinned points.
  std::map<std::size_t, std::vector<std::size_t>> by_match;
  std::map<std::size_t, Points2> query_points;
  for (std::size_t k = 0; k < closures.size(); ++k) {
    by_match[closures[k].match].push_back(k);
    query_points[closures[k].query];
  }
  std::vector<std::map<std::size_t, Points2>::iterator> queries;
  for (auto it = query_points.begin(); it != query_points.end(); ++it) queries.push_back(it);
  parallel_for(queries.size(), c.num_threads, [&](std::size_t i) {
    queries[i]->second = thinned(fine_points(scans, s, maps[queries[i]->first], window_length, c),
                                  static_cast<std::size_t>(c.max_points));
  });
  std::vector<const std::pair<const std::size_t, std::vector<std::size_t>>*> groups;
  for (const auto& g : by_match) groups.push_back(&g);
  ScanMatcherConfig matcher;
  matcher.resolution = c.resolution;
  matcher.sigma = c.sigma;
  matcher.linear_window = c.linear_window;
  matcher.angular_window = c.angular_window;
  parallel_for(groups.size(), c.num_threads, [&](std::size_t g) {
    const LikelihoodField field(fine_points(scans, s, maps[groups[g]->first], window_length, c), c.resolution, c.sigma);
    for (std::size_t k : groups[g]->second) {
      LoopClosure& l = closures[k];
      const ScanMatch m = match_scan(field, query_points.at(l.query), l.T_match_query, matcher);
      const Pose2 d = l.T_match_query.inverse() * m.pose;
      if (m.score > 0 && d.translation().norm() <= 2 * c.linear_window + 1e-9 &&
          std::abs(d.theta) <= 2 * c.angular_window + 1e-9)
        l.T_match_query = m.pose;
    }
  });
  return closures;
}

}  // namespace partslam
