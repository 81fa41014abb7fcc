// Ground-truth map-matching tasks (docs/DESIGN.md, "Tasks"; paper, "Map Matching Tasks"). Query q and global map g
// are a relevant pair when their poses (centroids) are within R and their travel distances differ by more
// than G (a loop closure). A task is q with a database of N maps: g plus N-1 random irrelevant maps (pose
// farther than 2R from q), in random order. Tasks are sampled with a seed and are reproducible.
#pragma once

#include <cstdint>
#include <vector>

#include "core/maps/submap.h"

namespace partslam {

struct TaskConfig {
  double radius = 2.0;          ///< R: max centroid distance of a relevant pair [m]
  double min_travel_gap = 20.0; ///< G: min travel difference of a relevant pair [m]
  int db_size = 100;            ///< N: maps per task database (relevant one included)
  int num_tasks = 500;          ///< tasks to sample (all relevant pairs when fewer)
  std::uint64_t seed = 1;       ///< sampling seed
};

/// Throws InputError naming the offending field.
void validate(const TaskConfig& config);

struct RelevantPair {
  std::size_t query = 0;   ///< index into the submap list
  std::size_t global = 0;  ///< index into the submap list
};

struct Task {
  std::size_t query = 0;              ///< index of the query submap
  std::size_t relevant = 0;           ///< index of the relevant global map
  std::vector<std::size_t> database;  ///< indices of the N database maps, relevant one included, shuffled
};

/// All ordered relevant pairs (q, g), q != g, in index order.
std::vector<RelevantPair> relevant_pairs(const Submaps& maps, const TaskConfig& config);

/// Samples the tasks. A query with fewer than N-1 irrelevant maps gets a smaller database.
std::vector<Task> make_tasks(const Submaps& maps, const TaskConfig& config);

/// True overlap of a pair: the share of the query's points that fall on the map's occupied cells (at
/// `resolution`, dilated by `dilation` cells, as dMM scores them) when placed by the ground-truth poses,
/// T_map_query = T_world_map(map)^-1 T_world_map(query). 0 for an empty query.
double true_overlap(const Submap& query, const Submap& map, double resolution = kMapResolution, int dilation = 1);

/// The ceiling no matcher can pass: the share of relevant pairs whose true overlap is below `threshold`
/// (0 when there is no pair). num_threads over maps; the result does not depend on it.
double low_overlap_share(const Submaps& maps, const std::vector<RelevantPair>& pairs, double threshold = 0.3,
                         int num_threads = 1);

/// Deterministic Fisher-Yates shuffle driven by std::mt19937_64 (same result on every standard library).
void seeded_shuffle(std::vector<std::size_t>& v, std::uint64_t seed);

}  // namespace partslam
