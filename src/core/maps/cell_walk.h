// The cells a segment crosses on a grid (Amanatides & Woo 1987), shared by the ray casting of occupancy grids
// (grid_map.cc) and the map check of `slam` (core/slam/map_check.cc).
#pragma once

#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/types.h"

namespace partslam {

/// Visits the cells of the segment a -> b, both in continuous cell coordinates (cell (x, y) covers [x, x + 1) x
/// [y, y + 1)), in order from a's cell: |bx - ax| + |by - ay| steps of one cell after it (cell indices of a and b),
/// so b's cell last. visit(x, y) returns true to stop; walk_cells returns whether it stopped.
template <typename Visit>
bool walk_cells(const Vec2& a, const Vec2& b, Visit&& visit) {
  int x = static_cast<int>(std::floor(a.x())), y = static_cast<int>(std::floor(a.y()));
  const int x_end = static_cast<int>(std::floor(b.x())), y_end = static_cast<int>(std::floor(b.y()));
  const Vec2 d = b - a;
  const int sx = d.x() > 0 ? 1 : -1, sy = d.y() > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double dx = d.x() != 0 ? std::abs(1.0 / d.x()) : inf, dy = d.y() != 0 ? std::abs(1.0 / d.y()) : inf;
  double tx = d.x() != 0 ? (d.x() > 0 ? x + 1 - a.x() : a.x() - x) * dx : inf;
  double ty = d.y() != 0 ? (d.y() > 0 ? y + 1 - a.y() : a.y() - y) * dy : inf;
  const int steps = std::abs(x_end - x) + std::abs(y_end - y);
  for (int i = 0; i <= steps; ++i) {
    if (visit(x, y)) return true;
    if (tx < ty) {
      x += sx, tx += dx;
    } else {
      y += sy, ty += dy;
    }
  }
  return false;
}

}  // namespace partslam
