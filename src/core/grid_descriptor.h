// Coarse occupancy grids as succinct map descriptors (docs/DESIGN.md, "Baselines and the succinct default").
// A stored map is the occupancy of an S x S grid over its crop box in the canonical frame (S = 11: 121 bits),
// one bit per cell: set when at least min_points of the map's points fall in it. A query is compared with a
// stored grid under each of the four quarter turns (two maps of one place differ by one, in the Manhattan
// frame) and each translation of the query's points on a lattice of `substeps` steps per cell within
// +-max_shift cells; the score is the best similarity over those poses. The query side is computed online
// from its points (the local map is at hand), so finer query translations cost no stored bits.
//   similarity kJaccard:  |A ∩ B| / |A ∪ B|                                   (the `grid` baseline)
//   similarity kTolerant: (|A ∩ dil(B)| + |dil(A) ∩ B|) / (|A| + |B|), dil = the 8-neighbourhood: a wall seen
//                         one cell off still counts (centroids of two views of a place differ by a fraction of
//                         a cell to a few cells).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/types.h"

namespace partslam {

enum class GridSimilarity { kJaccard, kTolerant, kCosine, kOverlap, kCount };

struct GridConfig {
  int cells = 11;            ///< S: cells per side (S^2 <= 128 bits)
  double box_size = 12.8;    ///< side of the square the grid covers, centred on the map frame's origin [m]
  int min_points = 1;        ///< points a cell needs to be occupied
  int keep_percent = 100;    ///< keep only the densest cells: those with at least the count of the
                             ///< keep_percent-th percentile (from the top) of the map's non-empty cells
  int max_shift = 1;         ///< query translations up to this many cells each way
  int substeps = 1;          ///< query translation steps per cell (1: whole cells)
  GridSimilarity similarity = GridSimilarity::kJaccard;
  /// Which points count: 0 every point; 1 only wall points (their 0.5 m neighbourhood is a line along x or y);
  /// 2 wall points in two channels, walls along x and walls along y (2 S^2 bits; S <= 8).
  int walls = 0;
  /// Hubness correction (as CSLS in word-vector retrieval): a stored map that resembles every map is a "hub"
  /// that outranks true matches. Offline, each stored map m gets mu_m, its mean similarity (as a query) to up
  /// to hub_sample other stored maps, kept in hub_bits bits; the score is sim(q, m) - hub_weight * mu_m.
  /// 0 = off.
  double hub_weight = 0.0;
  int hub_sample = 256;
  int hub_bits = 7;
};

/// Throws InputError naming the offending field.
void validate(const GridConfig& config);

/// S^2 occupancy bits, row-major (bit x + S y), in two 64-bit words.
struct GridBits {
  std::array<std::uint64_t, 2> words{0, 0};
  int count() const;
  bool operator==(const GridBits&) const = default;
};

/// The stored grid of a map (points in its canonical frame).
GridBits make_grid(const Points2& points, const GridConfig& config);

/// The 8-neighbourhood dilation of a grid of S x S cells (kTolerant).
GridBits dilate(const GridBits& grid, int cells);

/// The query's grids under every quarter turn and translation the config searches, and their dilations.
struct QueryGrids {
  std::vector<GridBits> grids, dilated;
};
QueryGrids make_query_grids(const Points2& points, const GridConfig& config);

/// Best similarity of the query grids with a stored grid (and its dilation, for kTolerant), in [0, 1].
double grid_similarity(const QueryGrids& query, const GridBits& stored, const GridBits& stored_dilated,
                       const GridConfig& config);

}  // namespace partslam
