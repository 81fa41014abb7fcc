// The inner loop of dMM's branch-and-bound (dmm.h): the sixteen children (i + a s, j + b s), a, b in {0..3},
// of a search node are bounded in one pass over the query points, one lookup each in a PackedLevel:
//   bound(a, b) = sum_x level(cell(x) + (i + a s, j + b s))
// which is Eq. 1 itself at pyramid level 0 and an upper bound of it above (max-pooling). The query cells are
// sorted by row, so points whose row misses the grid are skipped by binary search; a column off the grid is
// clamped onto the zero column that ends every packed row. Counts are 16-bit SIMD lanes, summed per chunk of
// 65535 points: with AVX2 (chosen at run time) eight cell indices are computed in one vector and each cell
// is broadcast to the sixteen lanes, masked and compared; else SSE2, else scalar.
#pragma once

#include <array>

#include "core/dmm.h"

namespace partslam {

/// Bounds of the children, child a + 4 b at index a + 4 b. use_avx2 = false forces the portable path (tests).
std::array<int, 16> child_bounds(const PackedLevel& packed, const RotatedQuery& query, int i, int j,
                                 bool use_avx2 = true);

/// Whether this CPU runs the AVX2 path.
bool cpu_has_avx2();

}  // namespace partslam
