#include "core/matching/dmm.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <functional>
#include <numbers>
#include <queue>
#include <span>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/maps/scan.h"
#include "core/matching/dmm_internal.h"

namespace partslam {
namespace {

constexpr double kPi = std::numbers::pi;

void require(bool ok, const std::string& message) {
  if (!ok) throw InputError("dmm config: " + message);
}

// Auto step (Cartographer's FastCorrelativeScanMatcher2D): the farthest point moves by at most one cell.
double auto_angular_step(const Points2& points, double resolution) {
  double d_max = 0.0;
  for (const Vec2& p : points) d_max = std::max(d_max, p.norm());
  if (d_max <= resolution) return kPi / 4;
  return std::acos(std::clamp(1.0 - resolution * resolution / (2.0 * d_max * d_max), -1.0, 1.0));
}

std::vector<double> search_angles(const DmmConfig& config, double step) {
  std::vector<double> angles;
  if (config.canonical) {
    const int n = static_cast<int>(std::floor(config.angular_window / step + 1e-9));
    for (int base = 0; base < config.canonical_turns; ++base) {
      for (int m = -n; m <= n; ++m) angles.push_back(base * 2 * kPi / config.canonical_turns + m * step);
    }
    // A wing's walls and the local map's agree up to a quarter turn: four families each.
    const int extra = static_cast<int>(std::floor(config.extra_window / step + 1e-9));
    for (const double offset : config.extra_directions) {
      for (int base = 0; base < 4; ++base) {
        for (int m = -extra; m <= extra; ++m) angles.push_back(base * kPi / 2 + offset + m * step);
      }
    }
  } else {
    const int n = std::max(1, static_cast<int>(std::ceil(2 * kPi / step - 1e-9)));
    for (int m = 0; m < n; ++m) angles.push_back(m * (2 * kPi / n));
  }
  return angles;
}

}  // namespace

namespace dmm_internal {

Range search_range(const RotatedQuery& r, const OccupancyGrid& grid, const DmmConfig& config) {
  Range range;
  if (r.x_max < r.x_min || grid.width == 0 || grid.height == 0) return range;
  range.i_lo = grid.x0 - r.x_max;
  range.i_hi = grid.x0 + grid.width - 1 - r.x_min;
  range.j_lo = grid.y0 - r.y_max;
  range.j_hi = grid.y0 + grid.height - 1 - r.y_min;
  if (config.linear_window > 0.0) {
    const int w = static_cast<int>(std::floor(config.linear_window / config.resolution + 1e-9));
    range.i_lo = std::max(range.i_lo, -w);
    range.i_hi = std::min(range.i_hi, w);
    range.j_lo = std::max(range.j_lo, -w);
    range.j_hi = std::min(range.j_hi, w);
  }
  return range;
}

void check_compatible(const PreparedQuery& query, const PreparedMap& map) {
  const auto same = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(a, b); };
  if (!same(query.config.resolution, map.config.resolution)) {
    throw InputError("dmm: the query was prepared at " + std::to_string(query.config.resolution) +
                     " m, the map at " + std::to_string(map.config.resolution) + " m: resolutions differ");
  }
  if (query.config.canonical != map.config.canonical) {
    throw InputError("dmm: the query and the map disagree on canonical (Manhattan-frame) matching");
  }
}

DmmResult make_result(const PreparedQuery& query, const DmmConfig& config, int inliers, int rotation, int i, int j) {
  DmmResult result;
  result.inliers = inliers;
  result.inlier_fraction = query.num_points > 0 ? static_cast<double>(inliers) / query.num_points : 0.0;
  if (rotation >= 0) {
    result.T_map_query = {i * config.resolution, j * config.resolution,
                          wrap_angle(query.rotations[static_cast<std::size_t>(rotation)].angle)};
  }
  return result;
}

std::vector<Range> search_ranges(const PreparedQuery& query, const PreparedMap& map) {
  std::vector<Range> ranges;
  ranges.reserve(query.rotations.size());
  for (const RotatedQuery& r : query.rotations) ranges.push_back(search_range(r, map.grid, map.config));
  return ranges;
}

}  // namespace dmm_internal

void validate(const DmmConfig& c) {
  require(c.resolution > 0.0 && std::isfinite(c.resolution),
          "resolution must be a positive finite number, got " + std::to_string(c.resolution));
  require(std::isfinite(c.linear_window), "linear_window must be finite (<= 0 means the whole target map)");
  require(c.linear_window / c.resolution <= 1e6, "linear_window / resolution is absurdly large");
  require(c.angular_window >= 0.0 && c.angular_window <= kPi / 4,
          "angular_window must be in [0, pi/4] rad, got " + std::to_string(c.angular_window));
  require(c.angular_step >= 0.0 && c.angular_step <= kPi / 2 && std::isfinite(c.angular_step),
          "angular_step must be in [0, pi/2] rad (0: automatic), got " + std::to_string(c.angular_step));
  require(c.angular_step == 0.0 || c.angular_step >= 1e-5, "angular_step must be 0 (automatic) or >= 1e-5 rad");
  require(c.canonical_turns == 4 || c.canonical_turns == 8,
          "canonical_turns must be 4 or 8, got " + std::to_string(c.canonical_turns));
  require(c.extra_directions.size() <= 8, "extra_directions: at most 8, got " + std::to_string(c.extra_directions.size()));
  for (const double d : c.extra_directions)
    require(std::abs(d) <= kPi / 4, "extra_directions must each be in [-pi/4, pi/4] rad, got " + std::to_string(d));
  require(c.extra_window >= 0.0 && c.extra_window <= kPi / 4,
          "extra_window must be in [0, pi/4] rad, got " + std::to_string(c.extra_window));
  require(c.dilation >= 0 && c.dilation <= 100, "dilation must be in [0, 100] cells, got " + std::to_string(c.dilation));
  require(c.search_depth >= 0 && c.search_depth <= 8,
          "search_depth must be in [0, 8] (0: automatic), got " + std::to_string(c.search_depth));
}

DmmConfig dmm_config_for_dictionary() {
  DmmConfig config;
  config.linear_window = 0.0;
  return config;
}

namespace {

// Refuses points spread over more than kMaxMapExtent: a map's grid pyramid grows with its area, and a query's
// rotation step shrinks with its extent (docs/NOTES.md has what a huge query cost without this check).
void check_extent(const Points2& points, const char* what) {
  if (const Box2 box = bounding_box(points); box.width() > kMaxMapExtent || box.height() > kMaxMapExtent) {
    char text[160];
    std::snprintf(text, sizeof text, "dMM: the %s's points span %.0f x %.0f m, more than the %.0f m limit "
                  "(a stray scan far from the rest?)", what, box.width(), box.height(), kMaxMapExtent);
    throw InputError(text);
  }
}

}  // namespace

PreparedQuery prepare_query(const Points2& points_query, const DmmConfig& config) {
  validate(config);
  for (const Vec2& p : points_query) {
    if (!p.allFinite() || p.norm() > 1e6) throw InputError("dmm: query point coordinates must be finite and < 1e6 m");
  }
  check_extent(points_query, "query");
  PreparedQuery query;
  query.config = config;
  query.resolution = config.resolution;
  query.num_points = static_cast<int>(points_query.size());
  query.angular_step = config.angular_step > 0.0 ? config.angular_step
                                                   : auto_angular_step(points_query, config.resolution);
  for (const double angle : search_angles(config, query.angular_step)) {
    RotatedQuery r;
    r.angle = angle;
    const double c = std::cos(angle), s = std::sin(angle);
    r.x.reserve(points_query.size());
    r.y.reserve(points_query.size());
    // Cells sorted by row (a stable counting sort), so that the search skips rows off the grid.
    std::vector<int> xs, ys;
    xs.reserve(points_query.size());
    ys.reserve(points_query.size());
    for (const Vec2& p : points_query) {
      xs.push_back(static_cast<int>(std::floor((c * p.x() - s * p.y()) / config.resolution)));
      ys.push_back(static_cast<int>(std::floor((s * p.x() + c * p.y()) / config.resolution)));
    }
    if (!ys.empty()) {
      const auto [y_lo, y_hi] = std::minmax_element(ys.begin(), ys.end());
      const int y0 = *y_lo;
      std::vector<int> start(static_cast<std::size_t>(*y_hi - y0) + 2, 0);
      for (const int y : ys) ++start[static_cast<std::size_t>(y - y0) + 1];
      for (std::size_t m = 1; m < start.size(); ++m) start[m] += start[m - 1];
      r.x.resize(xs.size());
      r.y.resize(ys.size());
      for (std::size_t k = 0; k < xs.size(); ++k) {
        const auto slot = static_cast<std::size_t>(start[static_cast<std::size_t>(ys[k] - y0)]++);
        r.x[slot] = xs[k];
        r.y[slot] = ys[k];
      }
    }
    if (!r.x.empty()) {
      const auto [x_lo, x_hi] = std::minmax_element(r.x.begin(), r.x.end());
      const auto [y_lo, y_hi] = std::minmax_element(r.y.begin(), r.y.end());
      r.x_min = *x_lo, r.x_max = *x_hi, r.y_min = *y_lo, r.y_max = *y_hi;
    }
    query.rotations.push_back(std::move(r));
  }
  return query;
}

PreparedMap prepare_map(const Points2& points_map, const DmmConfig& config) {
  validate(config);
  check_extent(points_map, "map");
  PreparedMap map;
  map.config = config;
  map.num_points = static_cast<int>(points_map.size());
  const OccupancyGrid grid = build_occupancy_grid(points_map, config.resolution, config.dilation);
  int depth = config.search_depth;
  if (depth == 0) {
    // Root blocks of 4^depth cells: about 2 x 2 of them across the translation window (or the whole target).
    const int cells = config.linear_window > 0.0
                          ? 2 * static_cast<int>(std::floor(config.linear_window / config.resolution + 1e-9)) + 1
                          : std::max(grid.width, grid.height);
    depth = 1;
    while (depth < 8 && (1 << (2 * depth)) * 2 < cells) ++depth;
  }
  const GridPyramid pyramid = build_grid_pyramid(grid, 2 * depth - 1);
  for (int d = 0; d < depth; ++d) {
    map.packed.push_back(build_packed_level(pyramid.levels[static_cast<std::size_t>(2 * d)], 1 << (2 * d)));
  }
  map.grid = grid;
  return map;
}

DmmResult match_dmm(const PreparedQuery& query, const PreparedMap& map) {
  return dmm_internal::match_dmm_above(query, map, -1);
}

DmmResult match_dmm_elsewhere(const PreparedQuery& query, const PreparedMap& map, std::span<const Pose2> avoid,
                              double min_distance, double min_angle, int bar) {
  dmm_internal::Exclusion exclusion(min_distance, min_angle, map.config.resolution);
  for (const Pose2& pose : avoid) {
    if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.theta))
      throw InputError("dmm: a pose to avoid must be finite");
    exclusion.add(query, pose.x / map.config.resolution, pose.y / map.config.resolution, pose.theta);
  }
  return dmm_internal::match_dmm_above(query, map, bar, &exclusion);
}

DmmResult match_dmm_elsewhere(const PreparedQuery& query, const PreparedMap& map, const Pose2& avoid,
                              double min_distance, double min_angle) {
  return match_dmm_elsewhere(query, map, std::span<const Pose2>(&avoid, 1), min_distance, min_angle);
}

std::vector<DmmResult> match_dmm_many(const PreparedQuery& query, std::span<const PreparedMap> maps, int top_k,
                                      int num_threads) {
  std::vector<const PreparedMap*> pointers;
  pointers.reserve(maps.size());
  for (const PreparedMap& m : maps) pointers.push_back(&m);
  return match_dmm_many(query, pointers, top_k, num_threads);
}

std::vector<DmmResult> match_dmm_many(const PreparedQuery& query, std::span<const PreparedMap* const> maps,
                                      int top_k, int num_threads) {
  for (const PreparedMap* m : maps) dmm_internal::check_compatible(query, *m);  // once, before any thread starts
  if (num_threads < 1) throw InputError("dmm: num_threads must be >= 1, got " + std::to_string(num_threads));
  std::vector<DmmResult> results(maps.size());
  if (top_k <= 0) {
    const auto n = static_cast<std::ptrdiff_t>(maps.size());
#pragma omp parallel for schedule(dynamic) num_threads(num_threads) if (num_threads > 1)
    for (std::ptrdiff_t m = 0; m < n; ++m) {
      results[static_cast<std::size_t>(m)] = match_dmm(query, *maps[static_cast<std::size_t>(m)]);
    }
    return results;
  }
  // Min-heap of the k best exact scores so far; its top is the bar a new map must beat.
  std::priority_queue<int, std::vector<int>, std::greater<>> best;
  for (std::size_t m = 0; m < maps.size(); ++m) {
    const int bar = static_cast<int>(best.size()) == top_k ? best.top() : -1;
    results[m] = dmm_internal::match_dmm_above(query, *maps[m], bar);
    if (!results[m].exact) continue;
    best.push(results[m].inliers);
    if (static_cast<int>(best.size()) > top_k) best.pop();
  }
  return results;
}

}  // namespace partslam
