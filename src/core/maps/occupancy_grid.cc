#include "core/maps/occupancy_grid.h"

#include <algorithm>
#include <string>

#include "core/error.h"

namespace partslam {

std::size_t OccupancyGrid::num_occupied() const {
  return static_cast<std::size_t>(std::count(cells.begin(), cells.end(), std::uint8_t{1}));
}

OccupancyGrid build_occupancy_grid(const Points2& points, double resolution, int dilation_cells) {
  if (!(resolution > 0.0) || !std::isfinite(resolution)) {
    throw InputError("occupancy grid: resolution must be a positive finite number, got " +
                     std::to_string(resolution));
  }
  if (dilation_cells < 0 || dilation_cells > 1000) {
    throw InputError("occupancy grid: dilation must be in [0, 1000] cells, got " + std::to_string(dilation_cells));
  }
  OccupancyGrid grid;
  grid.resolution = resolution;
  if (points.empty()) return grid;

  const Box2 box = bounding_box(points);
  const double limit = 1e9 * resolution;  // keeps lattice indices far inside int range
  if (!std::isfinite(box.x_min + box.x_max + box.y_min + box.y_max) || std::abs(box.x_min) > limit ||
      std::abs(box.x_max) > limit || std::abs(box.y_min) > limit || std::abs(box.y_max) > limit) {
    throw InputError("occupancy grid: point coordinates are not finite or too large for the lattice");
  }
  const Eigen::Vector2i lo = lattice_cell({box.x_min, box.y_min}, resolution);
  const Eigen::Vector2i hi = lattice_cell({box.x_max, box.y_max}, resolution);
  const std::int64_t w = static_cast<std::int64_t>(hi.x()) - lo.x() + 1 + 2 * dilation_cells;
  const std::int64_t h = static_cast<std::int64_t>(hi.y()) - lo.y() + 1 + 2 * dilation_cells;
  if (w * h > (std::int64_t{1} << 28)) {
    throw InputError("occupancy grid: " + std::to_string(w) + " x " + std::to_string(h) +
                     " cells is too large (extent / resolution too big)");
  }
  grid.x0 = lo.x() - dilation_cells;
  grid.y0 = lo.y() - dilation_cells;
  grid.width = static_cast<int>(w);
  grid.height = static_cast<int>(h);
  grid.cells.assign(static_cast<std::size_t>(w * h), 0);

  std::vector<Eigen::Vector2i> disc;
  for (int b = -dilation_cells; b <= dilation_cells; ++b) {
    for (int a = -dilation_cells; a <= dilation_cells; ++a) {
      if (a * a + b * b <= dilation_cells * dilation_cells) disc.emplace_back(a, b);
    }
  }
  for (const Vec2& p : points) {
    const Eigen::Vector2i c = lattice_cell(p, resolution);
    const int cx = c.x() - grid.x0, cy = c.y() - grid.y0;
    for (const Eigen::Vector2i& d : disc) {
      grid.cells[static_cast<std::size_t>(cy + d.y()) * grid.width + static_cast<std::size_t>(cx + d.x())] = 1;
    }
  }
  return grid;
}

GridPyramid build_grid_pyramid(const OccupancyGrid& base, int num_levels) {
  if (num_levels < 1 || num_levels > 16) {
    throw InputError("grid pyramid: num_levels must be in [1, 16], got " + std::to_string(num_levels));
  }
  GridPyramid pyramid;
  pyramid.levels.reserve(static_cast<std::size_t>(num_levels));
  pyramid.levels.push_back(base);
  for (int h = 1; h < num_levels; ++h) {
    const OccupancyGrid& prev = pyramid.levels.back();
    const int w = 1 << h, half = w / 2;
    OccupancyGrid level;
    level.resolution = base.resolution;
    level.x0 = base.x0 - w + 1;
    level.y0 = base.y0 - w + 1;
    level.width = base.width + w - 1;
    level.height = base.height + w - 1;
    level.cells.assign(static_cast<std::size_t>(level.width) * level.height, 0);
    if (base.width > 0 && base.height > 0) {
      // max over [x, x + w) = max of the previous level (windows of w / 2) at x and x + w / 2; in index
      // space level(cx, cy) = max of prev(cx - half .. cx, cy - half .. cy), prev reading 0 outside.
      // Vertical pass into `tall` (prev's columns, level's rows), then horizontal into the level.
      std::vector<std::uint8_t> tall(static_cast<std::size_t>(prev.width) * level.height, 0);
      for (int cy = 0; cy < level.height; ++cy) {
        std::uint8_t* out = &tall[static_cast<std::size_t>(cy) * prev.width];
        for (const int py : {cy - half, cy}) {
          if (py < 0 || py >= prev.height) continue;
          const std::uint8_t* in = &prev.cells[static_cast<std::size_t>(py) * prev.width];
          for (int cx = 0; cx < prev.width; ++cx) out[cx] = std::max(out[cx], in[cx]);
        }
      }
      for (int cy = 0; cy < level.height; ++cy) {
        const std::uint8_t* in = &tall[static_cast<std::size_t>(cy) * prev.width];
        std::uint8_t* out = &level.cells[static_cast<std::size_t>(cy) * level.width];
        for (int cx = 0; cx < prev.width; ++cx) {
          out[cx] = std::max(out[cx], in[cx]);
          out[cx + half] = std::max(out[cx + half], in[cx]);
        }
      }
    }
    pyramid.levels.push_back(std::move(level));
  }
  return pyramid;
}

PackedLevel build_packed_level(const OccupancyGrid& level, int step) {
  if (step < 1 || step > (1 << 20)) {
    throw InputError("packed level: step must be in [1, 2^20], got " + std::to_string(step));
  }
  PackedLevel packed;
  packed.step = step;
  if (level.width == 0 || level.height == 0) return packed;
  packed.x0 = level.x0 - 3 * step;
  packed.y0 = level.y0 - 3 * step;
  packed.width = level.width + 3 * step;
  packed.height = level.height + 3 * step;
  packed.cells.assign((static_cast<std::size_t>(packed.width) + 1) * packed.height + 1, 0);
  // Packed cell (cx, cy) takes bit a + 4 b from level cell (cx + (a - 3) step, cy + (b - 3) step).
  for (int b = 0; b < 4; ++b) {
    for (int a = 0; a < 4; ++a) {
      const int sx = (3 - a) * step, sy = (3 - b) * step;  // packed index = level index + shift
      for (int ly = 0; ly < level.height; ++ly) {
        const std::uint8_t* in = &level.cells[static_cast<std::size_t>(ly) * level.width];
        std::uint16_t* out = &packed.cells[static_cast<std::size_t>(ly + sy) * (packed.width + 1) + sx];
        for (int lx = 0; lx < level.width; ++lx) out[lx] = static_cast<std::uint16_t>(out[lx] | in[lx] << (a + 4 * b));
      }
    }
  }
  return packed;
}

int count_inliers(const Points2& points, const OccupancyGrid& grid, const Pose2& T_grid_points) {
  int inliers = 0;
  for (const Vec2& p : points) inliers += grid.at(T_grid_points * p);
  return inliers;
}

}  // namespace partslam
