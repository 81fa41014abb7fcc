// match_exhaustive (dmm.h): every candidate of dMM's discretisation scored, the reference the branch-and-bound
// searches are tested against and the speed baseline.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/matching/dmm.h"
#include "core/matching/dmm_internal.h"

namespace partslam {

DmmResult match_exhaustive(const PreparedQuery& query, const PreparedMap& map) {
  using dmm_internal::Range;
  using dmm_internal::check_compatible;
  using dmm_internal::make_result;
  using dmm_internal::search_range;
  check_compatible(query, map);
  const DmmConfig& config = map.config;
  const OccupancyGrid& grid = map.grid;
  int best_score = -1, best_rotation = -1, best_i = 0, best_j = 0;
  std::int64_t scored = 0;
  std::vector<int> acc;
  for (std::size_t k = 0; k < query.rotations.size(); ++k) {
    const RotatedQuery& r = query.rotations[k];
    const Range range = search_range(r, grid, config);
    if (range.empty()) continue;
    const int ni = range.i_hi - range.i_lo + 1, nj = range.j_hi - range.j_lo + 1;
    acc.assign(static_cast<std::size_t>(ni) * nj, 0);
    // Correlation, one query point at a time: contiguous rows of the grid are added to rows of the
    // accumulator, which the compiler vectorises.
    for (std::size_t p = 0; p < r.x.size(); ++p) {
      const int px = r.x[p], py = r.y[p];
      const int i_lo = std::max(range.i_lo, grid.x0 - px), i_hi = std::min(range.i_hi, grid.x0 + grid.width - 1 - px);
      const int j_lo = std::max(range.j_lo, grid.y0 - py), j_hi = std::min(range.j_hi, grid.y0 + grid.height - 1 - py);
      if (i_hi < i_lo) continue;
      for (int j = j_lo; j <= j_hi; ++j) {
        const std::uint8_t* row =
            &grid.cells[static_cast<std::size_t>(py + j - grid.y0) * grid.width + (px + i_lo - grid.x0)];
        int* out = &acc[static_cast<std::size_t>(j - range.j_lo) * ni + (i_lo - range.i_lo)];
        const int n = i_hi - i_lo + 1;
        for (int i = 0; i < n; ++i) out[i] += row[i];
      }
    }
    scored += static_cast<std::int64_t>(ni) * nj;
    for (int j = 0; j < nj; ++j) {
      for (int i = 0; i < ni; ++i) {
        const int s = acc[static_cast<std::size_t>(j) * ni + i];
        if (s > best_score) {
          best_score = s, best_rotation = static_cast<int>(k), best_i = range.i_lo + i, best_j = range.j_lo + j;
        }
      }
    }
  }
  DmmResult result = make_result(query, config, std::max(best_score, 0), best_rotation, best_i, best_j);
  result.candidates_scored = scored;
  return result;
}

}  // namespace partslam
