#include "core/slam/closure_refinement.h"

#include <algorithm>
#include <cmath>
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
  // The closures of each match (one likelihood field each), and each query side's thinned points.
  std::vector<std::vector<std::size_t>> by_match(maps.size());
  std::vector<std::size_t> matches, queries;
  for (std::size_t k = 0; k < closures.size(); ++k) {
    if (by_match[closures[k].match].empty()) matches.push_back(closures[k].match);
    by_match[closures[k].match].push_back(k);
    queries.push_back(closures[k].query);
  }
  std::sort(queries.begin(), queries.end());
  queries.erase(std::unique(queries.begin(), queries.end()), queries.end());
  std::vector<Points2> query_points(maps.size());
  parallel_for(queries.size(), c.num_threads, [&](std::size_t i) {
    const std::size_t q = queries[i];
    query_points[q] = thinned(fine_points(scans, s, maps[q], window_length, c), static_cast<std::size_t>(c.max_points));
  });
  ScanMatcherConfig matcher;
  matcher.resolution = c.resolution;
  matcher.sigma = c.sigma;
  matcher.linear_window = c.linear_window;
  matcher.angular_window = c.angular_window;
  parallel_for(matches.size(), c.num_threads, [&](std::size_t g) {
    const std::size_t match = matches[g];
    const LikelihoodField field(fine_points(scans, s, maps[match], window_length, c), c.resolution, c.sigma);
    for (std::size_t k : by_match[match]) {
      LoopClosure& l = closures[k];
      const ScanMatch m = match_scan(field, query_points[l.query], l.T_match_query, matcher);
      const Pose2 d = l.T_match_query.inverse() * m.pose;
      if (m.score > 0 && d.translation().norm() <= 2 * c.linear_window + 1e-9 &&
          std::abs(d.theta) <= 2 * c.angular_window + 1e-9)
        l.T_match_query = m.pose;
    }
  });
  return closures;
}

}  // namespace partslam
