// The inner loop of dMM's branch-and-bound (dmm.h): the sixteen children (i + a s, j + b s), a, b in {0..3},
// of a search node are bounded in one pass over the node's query cells, one lookup each in a PackedLevel:
//   bound(a, b) = sum_x level(cell(x) + (i + a s, j + b s))
// which is Eq. 1 itself at pyramid level 0 and an upper bound of it above (max-pooling). The looked-up value
// of a point says in which children it can score at all; a child's own pass then visits only those points
// (filter_cells), which is exact: a point that misses a block at a coarse level misses every translation in it.
// Cells are sorted by row, so points whose row misses the grid are skipped by binary search; a column off the
// grid is clamped onto the zero column that ends every packed row. Counts are 16-bit SIMD lanes, summed per
// chunk of 65535 points: with AVX2 (chosen at run time) eight cell indices are computed in one vector and each
// cell is broadcast to the sixteen lanes, masked and compared; else SSE2, else scalar.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/maps/occupancy_grid.h"

namespace partslam {

/// The query cells of one search node: one rotation's lattice cells, sorted by row (or a subsequence).
struct CellList {
  const int* x = nullptr;
  const int* y = nullptr;
  std::size_t size = 0;
};

/// Bounds of the children of the node at (i, j), child a + 4 b at index a + 4 b. values, when not null,
/// receives each point's looked-up cell (0 off the grid). The pass may stop early, returning false, once no
/// child bound can exceed bar; bounds and values are then incomplete. use_avx2 = false forces the portable path.
bool child_bounds(const PackedLevel& packed, const CellList& cells, int i, int j, int bar, std::uint16_t* values,
                  std::array<int, 16>& bounds, bool use_avx2 = true);

/// Appends, in order, the points of `cells` whose value has bit `bit` set to out_x / out_y (room for
/// cells.size each); returns how many.
std::size_t filter_cells(const CellList& cells, const std::uint16_t* values, int bit, int* out_x, int* out_y);

/// Whether this CPU runs the AVX2 path.
bool cpu_has_avx2();

}  // namespace partslam
