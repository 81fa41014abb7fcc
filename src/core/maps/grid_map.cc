#include "core/maps/grid_map.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/maps/cell_walk.h"

namespace partslam {
namespace {

void require_grid(bool ok, const std::string& message) {
  if (!ok) throw InputError("grid map: " + message);
}

}  // namespace

void validate(const GridMapConfig& c) {
  require_grid(std::isfinite(c.resolution) && c.resolution >= 0.005 && c.resolution <= 10.0,
               "resolution must be in [0.005, 10] m, got " + std::to_string(c.resolution));
  require_grid(std::isfinite(c.max_range) && c.max_range > 0.0, "max_range must be a positive finite number");
  require_grid(c.occupied_ratio > 0.0 && c.occupied_ratio <= 1.0, "occupied_ratio must be in (0, 1]");
  require_grid(std::isfinite(c.margin) && c.margin >= 0.0 && c.margin <= 100.0,
               "margin must be in [0, 100] m");
}

void validate(const GridMap& m) {
  require_grid(std::isfinite(m.resolution) && m.resolution > 0.0,
               "resolution must be a positive finite number");
  require_grid(std::isfinite(m.origin.x) && std::isfinite(m.origin.y) && std::isfinite(m.origin.theta) &&
                   std::abs(m.origin.x) <= kMaxCoordinate && std::abs(m.origin.y) <= kMaxCoordinate,
               "origin must be finite and within " + std::to_string(kMaxCoordinate) + " m");
  require_grid(
      m.width >= 0 && m.height >= 0 && m.cells.size() == static_cast<std::size_t>(m.width) * m.height,
      "cells do not match width x height");
  require_grid(m.width * m.resolution <= kMaxMapExtent && m.height * m.resolution <= kMaxMapExtent,
               "the map spans more than " + std::to_string(kMaxMapExtent) + " m");
}

GridMap build_grid_map(const Scans& scans, const GridMapConfig& config) {
  validate(config);
  Points2 corners;  // every endpoint and laser position, for the extent
  for (const Scan& s : scans) {
    const Points2 p = points_world(s, config.max_range);
    if (p.empty()) continue;
    const Box2 b = bounding_box(p);
    corners.insert(corners.end(), {{b.x_min, b.y_min}, {b.x_max, b.y_max}, s.T_world_laser.translation()});
  }
  require_grid(!corners.empty(), "no beam endpoint within max_range: nothing to map");
  const Box2 box = bounding_box(corners);
  require_grid(
      box.width() + 2 * config.margin <= kMaxMapExtent && box.height() + 2 * config.margin <= kMaxMapExtent,
      "the scans span more than " + std::to_string(kMaxMapExtent) + " m (a stray pose?)");
  const double r = config.resolution;
  GridMap map;
  map.resolution = r;
  map.origin = {std::floor((box.x_min - config.margin) / r) * r, std::floor((box.y_min - config.margin) / r) * r, 0.0};
  map.width = static_cast<int>(std::ceil((box.x_max + config.margin - map.origin.x) / r));
  map.height = static_cast<int>(std::ceil((box.y_max + config.margin - map.origin.y) / r));
  require_grid(static_cast<double>(map.width) * map.height <= double(1 << 28),
               "more than 2^28 cells: use a coarser resolution");
  std::vector<std::uint32_t> hits(static_cast<std::size_t>(map.width) * map.height, 0), passes(hits.size(), 0);
  const auto index = [&](int cx, int cy) { return static_cast<std::size_t>(cy) * map.width + cx; };
  for (const Scan& s : scans) {
    const Vec2 o = s.T_world_laser.translation();
    const Vec2 laser((o.x() - map.origin.x) / r, (o.y() - map.origin.y) / r);
    for (const Vec2& p : points_world(s, config.max_range)) {
      const Vec2 end((p.x() - map.origin.x) / r, (p.y() - map.origin.y) / r);
      // Cells crossed from the laser to the endpoint, the end cell excluded: the walk's first `steps` cells, up to
      // the end cell if it comes sooner.
      const int end_x = static_cast<int>(std::floor(end.x())), end_y = static_cast<int>(std::floor(end.y()));
      const int steps = std::abs(end_x - static_cast<int>(std::floor(laser.x()))) +
                        std::abs(end_y - static_cast<int>(std::floor(laser.y())));
      int visited = 0;
      walk_cells(laser, end, [&](int cx, int cy) {
        if (visited++ == steps || (cx == end_x && cy == end_y)) return true;
        ++passes[index(cx, cy)];
        return false;
      });
      ++hits[index(end_x, end_y)];
    }
  }
  map.cells.resize(hits.size(), CellState::kUnknown);
  for (std::size_t k = 0; k < hits.size(); ++k) {
    if (hits[k] > 0 && hits[k] >= config.occupied_ratio * (hits[k] + passes[k])) {
      map.cells[k] = CellState::kOccupied;
    } else if (passes[k] + hits[k] > 0) {
      map.cells[k] = CellState::kFree;
    }
  }
  return map;
}

Points2 occupied_points(const GridMap& map) {
  validate(map);
  Points2 points;
  for (int row = 0; row < map.height; ++row) {
    for (int column = 0; column < map.width; ++column) {
      if (map.at(column, row) == CellState::kOccupied) points.push_back(map.cell_centre(column, row));
    }
  }
  return points;
}

}  // namespace partslam
