// Coarse occupancy grids as succinct map descriptors (docs/DESIGN.md, "Baselines and the succinct default";
// docs/NOTES.md, "The succinct matcher"). A stored map is the occupancy of an S x S grid over a square box
// centred on its frame origin (its centroid) in the canonical frame, one bit per cell: set when at least
// min_points of the map's points fall in it. A query is compared with a stored grid under each of the four
// quarter turns (two maps of one place differ by one in the Manhattan frame) and each translation of the
// query's points on a lattice of `substeps` steps per cell within +-max_shift cells; the score is the best
// Jaccard similarity |A ∩ B| / |A ∪ B| over those poses. The query side is computed online from its points
// (the local map is at hand), so finer query translations cost no stored bits.
//
// Hubness correction (ours, after CSLS in cross-lingual word retrieval): some maps (long corridors, cluttered
// rooms) resemble every other map and outrank true matches. Offline, each stored map m gets mu_m, the mean
// best-pose similarity of the queries of up to hub_sample other stored maps (probes spread over the database)
// to m's grid, kept in hub_bits bits; the score becomes sim(q, m) - hub_weight * mu_m.
//
//   `grid[:S]`   the baseline: S = 11 (121 bits) over the 12.8 m crop, +-1 cell, whole-cell shifts, no hub.
// A ranking of a large database (index_min_maps) for its top k (RankOptions::top_k > 0, e.g. `partslam match
// --top K`) goes through the AVX-512 kernels of grid_cascade.h as an exact scan; the other maps then score
// -infinity.
//
//   `succinct`   the product's default <= 128-bit matcher: 11 x 11 over 8 m (0.73 m cells), +-4 cells in
//                half-cell steps, hub weight 1 with 7 bits of mu (121 + 7 = 128 bits).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/parallel.h"
#include "core/types.h"

namespace partslam {

struct GridConfig {
  int cells = 11;            ///< S: cells per side (S^2 <= 121 bits)
  double box_size = kCropSize;  ///< side of the square the grid covers, centred on the map frame's origin [m]
  int min_points = 1;        ///< points a cell needs to be occupied
  int max_shift = 1;         ///< query translations up to this many cells each way
  int substeps = 1;          ///< query translation steps per cell (1: whole cells)
  double hub_weight = 0.0;   ///< hubness correction weight (0 = off)
  int hub_sample = 256;      ///< probe maps (other stored maps' queries) mu_m is averaged over (at most)
  int hub_bits = 7;          ///< bits of the stored mu_m (levels over [0, 1])
  /// A ranker over at least this many stored maps answers top-k requests through grid_cascade.h's kernels as an
  /// exact scan (4.4x the scalar scan at 100 k maps; building it is a copy: docs/NOTES.md).
  std::size_t index_min_maps = 100'000;
  /// ... and over at least this many through the cascade's approximate stages (grid_cascade.h's defaults): at
  /// 10 M maps they find the relevant map in the top 100 as often as the exact scan, at 1 M not yet
  /// (docs/NOTES.md, "The succinct matcher at fleet scale").
  std::size_t cascade_min_maps = 10'000'000;
};

/// The configuration of `succinct`, chosen on the tuning split (docs/NOTES.md, "The succinct matcher").
GridConfig succinct_grid_config();

/// Throws InputError naming the offending field.
void validate(const GridConfig& config);

/// S^2 occupancy bits, row-major (bit x + S y), in two 64-bit words.
struct GridBits {
  std::array<std::uint64_t, 2> words{0, 0};
  int count() const;
  bool operator==(const GridBits&) const = default;
};

/// Stored bits per map: S^2, plus hub_bits when the hubness correction is on.
int grid_bits_per_map(const GridConfig& config);

/// The stored grid of a map (points in its canonical frame).
GridBits make_grid(const Points2& points, const GridConfig& config);

/// The query's grids under every quarter turn and translation the config searches.
std::vector<GridBits> make_query_grids(const Points2& points, const GridConfig& config);

/// Jaccard similarity of two grids (0 when both are empty).
double jaccard(const GridBits& a, const GridBits& b);

/// Best Jaccard similarity of the query grids with a stored grid, in [0, 1].
double grid_similarity(const std::vector<GridBits>& query, const GridBits& stored);
/// The same with the query grids' cell counts given (counts[v] = query[v].count()): what the ranker computes
/// per stored map.
double grid_similarity(const std::vector<GridBits>& query, const std::vector<int>& counts, const GridBits& stored);
/// The cell count of each grid.
std::vector<int> grid_counts(const std::vector<GridBits>& grids);

/// mu_m of each stored grid (the hubness correction above; points[m] are map m's points, for its query grids):
/// the mean best-pose similarity to m of the queries of up to hub_sample maps spread over the list (never m
/// itself), quantised to hub_bits; all 0 when hub_weight is 0 or there is one map. Same for any num_threads.
std::vector<double> grid_hubness(std::span<const Points2* const> points, const std::vector<GridBits>& stored,
                                 const GridConfig& config, int num_threads = 1, const Progress& progress = {});

}  // namespace partslam
