#include "core/slam/neighbour_refinement.h"

#include <algorithm>
#include <limits>
#include <string>

#include "core/error.h"
#include "core/matching/scan_matcher.h"
#include "core/parallel.h"
#include "core/slam/front_end.h"

namespace partslam {

void validate(const NeighbourRefinementConfig& c) {
  const auto fail = [](const std::string& what) { throw InputError("neighbour refinement config: " + what); };
  if (c.rounds < 0 || c.rounds > 100) fail("rounds must be in [0, 100], got " + std::to_string(c.rounds));
  if (c.window < 1 || c.window > 10000) fail("window must be in [1, 10000], got " + std::to_string(c.window));
  if (c.block < 1 || c.block > 10000) fail("block must be in [1, 10000], got " + std::to_string(c.block));
  if (!(c.sigma > 0 && c.sigma <= 1)) fail("sigma must be in (0, 1] m, got " + std::to_string(c.sigma));
  if (!(c.max_move > 0 && c.max_move <= 10)) fail("max_move must be in (0, 10] m, got " + std::to_string(c.max_move));
  if (c.num_threads < 1 || c.num_threads > 1024)
    fail("num_threads must be in [1, 1024], got " + std::to_string(c.num_threads));
}

Scans refine_on_neighbours(const Scans& scans, const NeighbourRefinementConfig& c, const FrontEndConfig& front_end,
                           NeighbourRefinementStats* stats) {
  validate(c);
  validate(front_end);
  Scans out = scans;
  if (c.rounds == 0 || scans.size() < 2) return out;
  std::vector<Points2> points(scans.size());
  parallel_for(scans.size(), c.num_threads, [&](std::size_t i) { points[i] = matching_points(scans[i], front_end); });
  ScanMatcherConfig gauss_newton = front_end.matcher;
  gauss_newton.sigma = c.sigma, gauss_newton.linear_window = 0, gauss_newton.angular_window = 0;
  gauss_newton.num_threads = 1;
  const std::size_t n = scans.size(), block = static_cast<std::size_t>(c.block),
                    window = static_cast<std::size_t>(c.window);
  const std::size_t blocks = (n + block - 1) / block;
  // Per scan and round: whether its refinement was taken, and how far it moved it.
  std::vector<char> taken(n, 0), too_far(n, 0);
  std::vector<double> moved(n, 0.0);
  NeighbourRefinementStats total;
  double moved_sum = 0;
  for (int round = 0; round < c.rounds; ++round) {
    std::vector<Pose2> before(n);  // the poses this round began with: every block reads these
    for (std::size_t i = 0; i < n; ++i) before[i] = out[i].T_world_laser;
    std::fill(taken.begin(), taken.end(), 0), std::fill(too_far.begin(), too_far.end(), 0);
    parallel_for(blocks, c.num_threads, [&](std::size_t b) {
      const std::size_t first = b * block, end = std::min(n, first + block);
      // The block's own points (world), to keep only the neighbours' points near them: the field covers the
      // block, not everything its neighbours saw.
      Vec2 lo = Vec2::Constant(std::numeric_limits<double>::max()), hi = -lo;
      for (std::size_t i = first; i < end; ++i)
        for (const Vec2& p : points[i]) {
          const Vec2 q = before[i] * p;
          lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
        }
      const Vec2 margin = Vec2::Constant(c.max_move + 3 * c.sigma + front_end.matcher.resolution);
      lo -= margin, hi += margin;
      Points2 near;
      for (std::size_t j = first >= window ? first - window : 0; j < std::min(n, end + window); ++j) {
        if (j >= first && j < end) continue;
        const Pose2::Applied to_world = before[j].applied();
        for (const Vec2& p : points[j]) {
          const Vec2 q = to_world(p);
          if ((q.array() >= lo.array()).all() && (q.array() <= hi.array()).all()) near.push_back(q);
        }
      }
      if (near.empty()) return;
      const LikelihoodField field(near, front_end.matcher.resolution, c.sigma);
      for (std::size_t i = first; i < end; ++i) {
        if (points[i].empty()) continue;
        const Pose2 refined = match_scan(field, points[i], before[i], gauss_newton).pose;
        const double d = (refined.translation() - before[i].translation()).norm();
        if (d > c.max_move) {
          too_far[i] = 1;
          continue;
        }
        out[i].T_world_laser = refined;
        taken[i] = 1, moved[i] = d;
      }
    });
    for (std::size_t i = 0; i < n; ++i) {
      total.refined += static_cast<std::size_t>(taken[i]);
      total.too_far += static_cast<std::size_t>(too_far[i]);
      if (taken[i]) moved_sum += moved[i];
    }
  }
  total.mean_move = total.refined > 0 ? moved_sum / static_cast<double>(total.refined) : 0.0;
  if (stats) *stats = total;
  return out;
}

}  // namespace partslam
