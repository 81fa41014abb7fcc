// Binary occupancy grids for direct map matching (docs/DESIGN.md, "dMM"): P_Y of the paper's Eq. 1 is 1 on an
// occupied cell of Y's grid, optionally dilated. Every grid lives on the global lattice of its resolution r:
// lattice cell (x, y) covers [x r, (x + 1) r) x [y r, (y + 1) r) of the map frame, so a point set discretised
// once (floor(p / r)) can be looked up in any grid of the same resolution without re-discretising.
//
// The max-pooled pyramid is Cartographer's PrecomputationGridStack2D (Hess et al. 2016, Sec. V.C): level h holds
// at lattice cell (x, y) the maximum of the base grid over [x, x + 2^h) x [y, y + 2^h), so the sum of a point
// set's level-h values at a translation bounds from above the score of every translation in the 2^h x 2^h block.
#pragma once

#include <cstdint>
#include <vector>

#include "core/types.h"

namespace partslam {

/// Lattice cell of a point: (floor(x / r), floor(y / r)).
inline Eigen::Vector2i lattice_cell(const Vec2& p, double resolution) {
  return {static_cast<int>(std::floor(p.x() / resolution)), static_cast<int>(std::floor(p.y() / resolution))};
}

/// A binary grid over the lattice cells [x0, x0 + width) x [y0, y0 + height); cells outside read 0.
struct OccupancyGrid {
  double resolution = kMapResolution;  ///< cell side [m]
  int x0 = 0;               ///< lattice index of the first column
  int y0 = 0;               ///< lattice index of the first row
  int width = 0;            ///< columns
  int height = 0;           ///< rows
  std::vector<std::uint8_t> cells;  ///< row-major, 0 or 1

  /// Value of lattice cell (x, y); 0 outside the grid.
  std::uint8_t at(int x, int y) const {
    const unsigned cx = static_cast<unsigned>(x - x0), cy = static_cast<unsigned>(y - y0);
    return cx < static_cast<unsigned>(width) && cy < static_cast<unsigned>(height)
               ? cells[static_cast<std::size_t>(cy) * static_cast<std::size_t>(width) + cx]
               : std::uint8_t{0};
  }
  std::uint8_t at(const Vec2& p) const {
    const Eigen::Vector2i c = lattice_cell(p, resolution);
    return at(c.x(), c.y());
  }
  /// Map-frame box covered by the grid [m].
  Box2 extent() const {
    return {x0 * resolution, (x0 + width) * resolution, y0 * resolution, (y0 + height) * resolution};
  }
  std::size_t num_occupied() const;
};

/// The grid of a point set: a cell is 1 when a point falls in it or lies within dilation_cells (Euclidean, in
/// cells) of such a cell. The grid is the points' cell bounding box grown by dilation_cells on every side.
/// An empty point set gives an empty grid. Throws InputError for resolution <= 0, dilation_cells < 0 or a grid
/// of more than 2^28 cells.
OccupancyGrid build_occupancy_grid(const Points2& points, double resolution, int dilation_cells = 0);

/// Max-pooled levels 0..num_levels-1; level h is a grid whose lattice cell (x, y) holds the maximum of the base
/// grid over [x, x + 2^h) x [y, y + 2^h), stored over x in [base.x0 - 2^h + 1, base.x0 + base.width), same in y.
struct GridPyramid {
  std::vector<OccupancyGrid> levels;  ///< levels[0] is the base grid
};

/// Throws InputError for num_levels outside [1, 16].
GridPyramid build_grid_pyramid(const OccupancyGrid& base, int num_levels);

/// A 4 x 4 block of cells of one pyramid level in 16 bits, so that a single lookup per query point bounds all
/// sixteen children of a branch-and-bound node: bit a + 4 b of lattice cell (x, y) is
/// level.at(x + a step, y + b step), a, b in {0, 1, 2, 3}. Stored over x in [level.x0 - 3 step, level.x0 +
/// level.width), same in y; cells outside read 0.
struct PackedLevel {
  int step = 1;   ///< offset between the packed cells [cells]; 2^h for pyramid level h
  int x0 = 0;     ///< lattice index of the first column
  int y0 = 0;     ///< lattice index of the first row
  int width = 0;  ///< columns
  int height = 0; ///< rows
  /// Row-major with stride width + 1: every row ends in a 0, which lookups left or right of the grid may read;
  /// one more 0 at the end lets SIMD gathers read 32 bits at the last cell.
  std::vector<std::uint16_t> cells;

  std::uint16_t at(int x, int y) const {
    const unsigned cx = static_cast<unsigned>(x - x0), cy = static_cast<unsigned>(y - y0);
    return cx < static_cast<unsigned>(width) && cy < static_cast<unsigned>(height)
               ? cells[static_cast<std::size_t>(cy) * (static_cast<std::size_t>(width) + 1) + cx]
               : std::uint16_t{0};
  }
};

/// Throws InputError for step outside [1, 2^20].
PackedLevel build_packed_level(const OccupancyGrid& level, int step);

/// Eq. 1 at one pose: the number of points p with grid.at(T_grid_points * p) == 1.
int count_inliers(const Points2& points, const OccupancyGrid& grid, const Pose2& T_grid_points);

}  // namespace partslam
