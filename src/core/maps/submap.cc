#include "core/maps/submap.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_map>

#include "core/error.h"
#include "core/maps/manhattan.h"

namespace partslam {

void validate(const SubmapConfig& c) {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      throw InputError(std::string("submap config: ") + name + " must be a positive finite number, got " +
                       std::to_string(v));
    }
  };
  positive(c.window_length, "window_length");
  positive(c.spacing, "spacing");
  positive(c.resolution, "resolution");
  positive(c.crop_size, "crop_size");
  // A local map's stretch of travel: a window past any log's length labels a stretch that is not there.
  if (c.window_length > 10000.0 || c.spacing > 10000.0)
    throw InputError("submap config: window_length and spacing must be at most 10000 m, got " +
                     std::to_string(c.window_length) + " and " + std::to_string(c.spacing));
  if (!(c.max_range > 0.0)) throw InputError("submap config: max_range must be > 0 [m], got " + std::to_string(c.max_range));
  if (c.crop_size / c.resolution > 100000) throw InputError("submap config: crop_size / resolution is absurdly large");
  if (c.min_points < 1) throw InputError("submap config: min_points must be >= 1");
}

std::vector<double> travel_distances(const Scans& scans) {
  std::vector<double> s(scans.size(), 0.0);
  for (std::size_t i = 1; i < scans.size(); ++i) {
    s[i] = s[i - 1] + (scans[i].T_world_laser.translation() - scans[i - 1].T_world_laser.translation()).norm();
  }
  return s;
}

Points2 voxel_downsample(const Points2& points, double resolution) {
  struct Cell {
    Vec2 sum = Vec2::Zero();
    int count = 0;
    std::size_t order = 0;
  };
  std::unordered_map<std::uint64_t, Cell> cells;
  cells.reserve(points.size());
  for (const Vec2& p : points) {
    const auto ix = static_cast<std::int64_t>(std::floor(p.x() / resolution));
    const auto iy = static_cast<std::int64_t>(std::floor(p.y() / resolution));
    const std::uint64_t key = (static_cast<std::uint64_t>(ix) << 32) ^ static_cast<std::uint32_t>(iy);
    auto [it, inserted] = cells.try_emplace(key);
    if (inserted) it->second.order = cells.size() - 1;
    it->second.sum += p;
    ++it->second.count;
  }
  // Emit in first-seen order so the result does not depend on hash-table iteration order.
  Points2 out(cells.size());
  for (const auto& [key, cell] : cells) out[cell.order] = cell.sum / cell.count;
  return out;
}

namespace {

// A local map of points in the world frame: one per cell, centred, aligned and cropped; nullopt when fewer
// than min_points remain. Sets points, alignment_angle and T_world_map.
std::optional<Submap> shape_local_map(const Points2& points_world, const SubmapConfig& config) {
  Submap m;
  const Points2 world = voxel_downsample(points_world, config.resolution);
  if (world.empty()) return std::nullopt;
  const Vec2 c = centroid(world);
  const double half = config.crop_size / 2.0;
  // The alignment angle comes from the points within the crop's inscribed circle (a rotation-invariant
  // region); the square crop is then taken in the canonical frame, so points stay inside +-crop_size / 2.
  Points2 centred, disc;
  centred.reserve(world.size());
  for (const Vec2& p : world) {
    centred.push_back(p - c);
    if (centred.back().norm() < half) disc.push_back(centred.back());
  }
  m.alignment_angle = config.align ? manhattan_angle(disc) : 0.0;
  const Pose2 T_map_centred{0.0, 0.0, m.alignment_angle};
  for (const Vec2& p : centred) {
    const Vec2 q = T_map_centred * p;
    if (std::abs(q.x()) < half && std::abs(q.y()) < half) m.points.push_back(q);
  }
  if (static_cast<int>(m.points.size()) < config.min_points) return std::nullopt;
  m.T_world_map = Pose2{c.x(), c.y(), 0.0} * T_map_centred.inverse();
  return m;
}

// The submap of scans [first, end): their points within max_range, shaped as above.
std::optional<Submap> build_one(const Scans& scans, const std::vector<double>& s, std::size_t first, std::size_t end,
                                const SubmapConfig& config) {
  Points2 world, origins_world;
  std::vector<double> timestamps;
  for (std::size_t j = first; j < end; ++j) {
    const Points2 pts = points_world(scans[j], config.max_range);
    world.insert(world.end(), pts.begin(), pts.end());
    timestamps.push_back(scans[j].timestamp);
    const Vec2 o = scans[j].T_world_laser.translation();
    if (origins_world.empty() || (o - origins_world.back()).norm() >= kOriginSpacing) origins_world.push_back(o);
  }
  std::optional<Submap> m = shape_local_map(world, config);
  if (!m) return std::nullopt;
  m->origins = transform(m->T_world_map.inverse(), origins_world);
  m->anchor_scan = static_cast<std::int64_t>(first);
  m->anchor_timestamp = scans[first].timestamp;
  m->travel = s[first];
  m->scan_timestamps = std::move(timestamps);
  return m;
}

}  // namespace

Submaps build_submaps(const Scans& scans, const SubmapConfig& config) {
  validate(config);
  const std::vector<double> s = travel_distances(scans);
  Submaps submaps;
  // Anchors: the first scan at or past each multiple of the spacing, so that there is one submap per
  // `spacing` of travel whatever the scan spacing (restarting the count at each anchor would add the
  // overshoot every time: 0.6 m instead of 0.5 m with scans every 0.1 m). The travel is a sum of
  // floating-point steps, so a multiple reached up to rounding counts as reached.
  const double tolerance = 1e-9 * std::max(1.0, s.empty() ? 0.0 : s.back());
  double next_anchor = 0.0;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    if (s[i] < next_anchor - tolerance) continue;
    next_anchor = (std::floor((s[i] + tolerance) / config.spacing) + 1.0) * config.spacing;
    std::size_t end = i;
    while (end < scans.size() && s[end] < s[i] + config.window_length) ++end;
    std::optional<Submap> m = build_one(scans, s, i, end, config);
    if (!m) continue;
    m->id = static_cast<std::int64_t>(submaps.size());
    submaps.push_back(std::move(*m));
  }
  return submaps;
}

Submap build_local_map(const Scans& scans, double from, double to, const SubmapConfig& config) {
  validate(config);
  if (!(from >= 0.0) || !(to > from) || !std::isfinite(to))
    throw InputError("local map: need 0 <= from < to [m of travel], got from " + std::to_string(from) + ", to " +
                     std::to_string(to));
  const std::vector<double> s = travel_distances(scans);
  std::size_t first = 0;
  while (first < scans.size() && s[first] < from) ++first;
  std::size_t end = first;
  while (end < scans.size() && s[end] < to) ++end;
  if (first == end)
    throw InputError("local map: no scan between " + std::to_string(from) + " and " + std::to_string(to) +
                     " m of travel (the log covers " + std::to_string(s.empty() ? 0.0 : s.back()) + " m)");
  std::optional<Submap> m = build_one(scans, s, first, end, config);
  if (!m)
    throw InputError("local map: fewer than " + std::to_string(config.min_points) + " points between " +
                     std::to_string(from) + " and " + std::to_string(to) + " m of travel");
  return *m;
}

Submap local_map_from_points(const Points2& points, const SubmapConfig& config, const Points2& origins) {
  validate(config);
  const auto check = [](const Points2& xs, const char* what) {
    for (const Vec2& p : xs) {
      if (!p.allFinite() || p.cwiseAbs().maxCoeff() > kMaxCoordinate)
        throw InputError(std::string("local map: ") + what + " coordinates must be finite and within " +
                         std::to_string(kMaxCoordinate) + " m");
    }
  };
  check(points, "point");
  check(origins, "laser origin");
  std::optional<Submap> m = shape_local_map(points, config);
  if (!m)
    throw InputError("local map: " + std::to_string(points.size()) + " points give fewer than " +
                     std::to_string(config.min_points) + " cells of " + std::to_string(config.resolution) + " m");
  m->origins = transform(m->T_world_map.inverse(), origins);
  return *m;
}

}  // namespace partslam
