#include "core/matching/dmm_ransac.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/random.h"

namespace partslam {
namespace {

void require_ransac(bool ok, const std::string& message) {
  if (!ok) throw InputError("dmm-ransac config: " + message);
}

std::size_t draw(Rng& rng, std::size_t n) { return static_cast<std::size_t>(rng.index(n)); }

// Rigid transform mapping the segment x1-x2 onto y1-y2 (least squares for equal lengths: the midpoints match).
Pose2 hypothesis(const Vec2& x1, const Vec2& x2, const Vec2& y1, const Vec2& y2) {
  const Vec2 dx = x2 - x1, dy = y2 - y1;
  const double theta = wrap_angle(std::atan2(dy.y(), dy.x()) - std::atan2(dx.y(), dx.x()));
  const Vec2 t = 0.5 * (y1 + y2) - Eigen::Rotation2Dd(theta) * (0.5 * (x1 + x2));
  return {t.x(), t.y(), theta};
}

int score(const Points2& points, const OccupancyGrid& grid, const Pose2& T) {
  const double c = std::cos(T.theta), s = std::sin(T.theta), inv = 1.0 / grid.resolution;
  int inliers = 0;
  for (const Vec2& p : points) {
    const double x = c * p.x() - s * p.y() + T.x, y = s * p.x() + c * p.y() + T.y;
    inliers += grid.at(static_cast<int>(std::floor(x * inv)), static_cast<int>(std::floor(y * inv)));
  }
  return inliers;
}

}  // namespace

void validate(const DmmRansacConfig& c) {
  require_ransac(c.iterations >= 0 && c.iterations <= 100000000,
                 "iterations must be in [0, 1e8], got " + std::to_string(c.iterations));
  require_ransac(c.inlier_distance >= 0.0 && std::isfinite(c.inlier_distance),
                 "inlier_distance must be a finite number >= 0, got " + std::to_string(c.inlier_distance));
  require_ransac(c.resolution > 0.0 && std::isfinite(c.resolution),
                 "resolution must be a positive finite number, got " + std::to_string(c.resolution));
  require_ransac(c.inlier_distance / c.resolution <= 100,
                 "inlier_distance / resolution must be <= 100 cells");
  require_ransac(
      c.min_sample_distance >= 0.0 && std::isfinite(c.min_sample_distance),
      "min_sample_distance must be a finite number >= 0, got " + std::to_string(c.min_sample_distance));
  require_ransac(c.length_tolerance >= 0.0 && std::isfinite(c.length_tolerance),
                 "length_tolerance must be a finite number >= 0, got " + std::to_string(c.length_tolerance));
  require_ransac(c.angular_window >= 0.0 && c.angular_window <= std::numbers::pi / 4,
                 "angular_window must be in [0, pi/4] rad, got " + std::to_string(c.angular_window));
  require_ransac(c.max_draws >= 1 && c.max_draws <= 1000000,
                 "max_draws must be in [1, 1e6], got " + std::to_string(c.max_draws));
}

PreparedRansacMap prepare_ransac_map(const Points2& points_map, const DmmRansacConfig& config) {
  validate(config);
  PreparedRansacMap map;
  map.points = points_map;
  map.inlier_grid = build_occupancy_grid(points_map, config.resolution,
                                         static_cast<int>(std::lround(config.inlier_distance / config.resolution)));
  return map;
}

DmmResult match_dmm_ransac(const Points2& query, const PreparedRansacMap& map, const DmmRansacConfig& config) {
  validate(config);
  for (const Vec2& p : query) {
    if (!p.allFinite() || p.norm() > 1e6) throw InputError("dmm-ransac: query points must be finite and < 1e6 m");
  }
  if (std::abs(map.inlier_grid.resolution - config.resolution) > 1e-9 * config.resolution) {
    throw InputError("dmm-ransac: map prepared at " + std::to_string(map.inlier_grid.resolution) +
                     " m, config resolution " + std::to_string(config.resolution) + " m");
  }
  DmmResult best;
  best.inliers = -1;
  const Points2& ys = map.points;
  if (!query.empty() && !ys.empty()) {
    Rng rng(config.seed);
    for (int it = 0; it < config.iterations && best.inliers < static_cast<int>(query.size()); ++it) {
      for (int d = 0; d < config.max_draws; ++d) {
        const Vec2& x1 = query[draw(rng, query.size())];
        const Vec2& x2 = query[draw(rng, query.size())];
        const double length = (x2 - x1).norm();
        if (length < config.min_sample_distance || length == 0.0) continue;
        const Vec2& y1 = ys[draw(rng, ys.size())];
        // Second correspondence: the first map point from a random start that is consistent with (x1, x2, y1).
        const double lo = std::max(0.0, length - config.length_tolerance), hi = length + config.length_tolerance;
        const double lo2 = lo * lo, hi2 = hi * hi;
        const Vec2 dx = x2 - x1;
        // Canonical: the angle between x2 - x1 and y2 - y1 is within the window of a multiple of 90 degrees,
        // i.e. min(|sin|, |cos|) <= sin(window) (tested on cross and dot products, no trigonometry).
        const double sin_window = std::sin(config.angular_window);
        const std::size_t start = draw(rng, ys.size());
        const Pose2* found = nullptr;
        Pose2 T;
        for (std::size_t k = 0; k < ys.size() && !found; ++k) {
          const std::size_t m = start + k < ys.size() ? start + k : start + k - ys.size();
          const Vec2& y2 = ys[m];
          const double d2 = (y2 - y1).squaredNorm();
          if (d2 < lo2 || d2 > hi2) continue;
          if (config.canonical) {
            const Vec2 dy = y2 - y1;
            const double cross = std::abs(dx.x() * dy.y() - dx.y() * dy.x()), dot = std::abs(dx.dot(dy));
            if (std::min(cross, dot) > sin_window * length * std::sqrt(d2)) continue;
          }
          T = hypothesis(x1, x2, y1, y2);
          found = &T;
        }
        if (!found) continue;
        ++best.candidates_scored;
        const int inliers = score(query, map.inlier_grid, T);
        if (inliers > best.inliers) {
          best.inliers = inliers;
          best.T_map_query = T;
        }
        break;
      }
    }
  }
  best.inliers = std::max(best.inliers, 0);
  best.inlier_fraction = query.empty() ? 0.0 : static_cast<double>(best.inliers) / static_cast<double>(query.size());
  return best;
}

}  // namespace partslam
