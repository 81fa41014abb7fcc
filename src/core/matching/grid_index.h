// An exact index for the succinct matcher's top k (grid_descriptor.h; its measured speed is in docs/NOTES.md,
// "A top-k index for the succinct matcher": the tree itself prunes little, the gain is the per-map pose-group
// bounds). The score of stored map m for a query is
//   s(m) = max over the query's poses v of J(q_v, g_m)  -  hub_weight * mu_m        (J: Jaccard similarity)
// and a scan computes it for every stored map (S = 17 translations a side and 4 turns: 1156 poses per map).
//
// The index is a binary tree over the stored grids. Each node keeps the union U and the intersection I of its
// maps' grids, the least and greatest cell count (b_min, b_max) and the least mu. For any map g of the node and
// any query grid q of a pose (or of a group of poses, with their union and intersection and counts a_min..a_max):
//   |q ∩ g| <= c_max = min(|q ∩ U|, a_max, b_max)
//   |q ∪ g| >= u_min = max(|q ∪ I|, a_min, b_min, a_min + b_min - c_max)
// so J(q, g) <= c_max / u_min, and s(m) <= that minus hub_weight * (least mu). A best-first search takes nodes
// in order of this bound and stops when no node can beat the k-th best exact score found; a leaf's maps are
// scored exactly over the pose groups whose own bound can still beat it. The tree splits a node around two
// far-apart maps (each map joins the one it is more like), so the maps of a node resemble one another (tight U
// and I).
//
// The result equals the linear scan's top k exactly (scores bit for bit, ties by lower index), because every
// bound is computed with the same correctly rounded operations as the score and rounding is monotone.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/matching/grid_descriptor.h"

namespace partslam {

/// A query as the index sees it: its grids under every pose (make_query_grids order: turn, then row shift,
/// then column shift) in groups of up to group_side x group_side neighbouring translations of one turn.
class GridQuery {
 public:
  GridQuery(std::vector<GridBits> grids, const GridConfig& config, int group_side = 4);

  struct Group {
    GridBits all_union, all_common;  // union and intersection of the group's grids
    int min_count = 0, max_count = 0;
    std::vector<std::uint32_t> poses;  // indices into grids()
  };
  const std::vector<GridBits>& grids() const { return grids_; }
  const std::vector<int>& counts() const { return counts_; }
  const std::vector<Group>& groups() const { return groups_; }

 private:
  std::vector<GridBits> grids_;
  std::vector<int> counts_;
  std::vector<Group> groups_;
};

struct GridMatch {
  std::size_t index = 0;  ///< the stored map's index
  double score = 0;       ///< s(m), exactly what the scan computes
  bool operator==(const GridMatch&) const = default;
};

struct GridSearchStats {
  std::size_t nodes_visited = 0;  ///< tree nodes whose bound was computed
  std::size_t maps_scored = 0;    ///< stored maps whose own bound (exact where it matters) was computed
  std::size_t poses_scored = 0;   ///< per-pose bounds computed (nodes and maps)
};

struct GridIndexConfig {
  int leaf_size = 32;        ///< maps per leaf (at most)
};

/// Throws InputError naming the offending field.
void validate(const GridIndexConfig& config);

class GridIndex {
 public:
  /// grids[i] and mu[i] are stored map i's grid and hubness (mu may be empty: all 0). Deterministic.
  GridIndex(std::vector<GridBits> grids, std::vector<double> mu, double hub_weight,
            const GridIndexConfig& config = {});

  /// The k best stored maps, best first (score descending, then index ascending): equal to scan_top_k.
  std::vector<GridMatch> top_k(const GridQuery& query, std::size_t k, GridSearchStats* stats = nullptr) const;

  std::size_t size() const { return index_.size(); }
  /// Bytes held (per-map grids, mu and indices, and the nodes).
  std::size_t memory_bytes() const;

 private:
  struct Node {
    GridBits all_union, all_common;
    std::uint8_t min_count = 0, max_count = 0;
    double min_mu = 0;
    std::uint32_t begin = 0, end = 0;  // maps [begin, end) in storage order
    std::int32_t left = -1, right = -1;
  };
  std::int32_t build(std::uint32_t begin, std::uint32_t end, const GridIndexConfig& config);

  double hub_weight_;
  std::vector<GridBits> grids_;       // storage order
  std::vector<double> mu_;            // storage order
  std::vector<std::uint32_t> index_;  // storage order -> map index
  std::vector<Node> nodes_;
};

/// The reference: every stored map's score, then the k best (score descending, then index ascending).
std::vector<GridMatch> scan_top_k(const GridQuery& query, const std::vector<GridBits>& grids,
                                  const std::vector<double>& mu, double hub_weight, std::size_t k);

}  // namespace partslam
