// Private to dMM's .cc files (dmm.h's searches): what the depth-first branch-and-bound
// (dmm_branch_and_bound.cc), the best-first DmmSearch (dmm_search.cc), the joint search (dmm_joint.cc) and
// the exhaustive reference (dmm_exhaustive.cc) share. A named namespace, not an anonymous one:
// DmmSearch::State, a class of the public header, holds these types, which GCC accepts from an anonymous
// namespace only in a file compiled on its own (outside the unity build's batches).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/matching/dmm.h"
#include "core/matching/dmm_bounds.h"

namespace partslam::dmm_internal {

// Translation range (in cells) searched for one rotation: the window intersected with the translations at
// which at least one rotated query cell lands on the target grid (all others score 0).
struct Range {
  int i_lo = 0, i_hi = -1, j_lo = 0, j_hi = -1;
  bool empty() const { return i_hi < i_lo || j_hi < j_lo; }
};

Range search_range(const RotatedQuery& r, const OccupancyGrid& grid, const DmmConfig& config);
// search_range of each of the query's rotations on the map.
std::vector<Range> search_ranges(const PreparedQuery& query, const PreparedMap& map);

// The query and the map were prepared with their own configs (validated then); they must share the lattice
// and the kind of rotation search. The map's config decides the translation window (its pyramid depth was
// chosen for it).
void check_compatible(const PreparedQuery& query, const PreparedMap& map);

DmmResult make_result(const PreparedQuery& query, const DmmConfig& config, int inliers, int rotation, int i,
                      int j);

// Bounds the sixteen children of the node at (i, j) over `cells` with `packed` (child_bounds; values as
// there) and calls emit(i, j, bound, bit) for each child inside the search range r, bit = a + 4 b its index;
// returns how many: none when the pass proved that no child beats bar.
template <typename Emit>
int bound_children(const PackedLevel& packed, const Range& r, const CellList& cells, int i, int j, int bar,
                   std::uint16_t* values, Emit&& emit) {
  std::array<int, 16> bounds;
  if (!child_bounds(packed, cells, i, j, bar, values, bounds)) return 0;
  int count = 0;
  for (int b = 0; b < 4; ++b) {
    const int cj = j + b * packed.step;
    if (cj > r.j_hi) break;
    for (int a = 0; a < 4; ++a) {
      const int ci = i + a * packed.step;
      if (ci > r.i_hi) break;
      emit(ci, cj, bounds[static_cast<std::size_t>(a + 4 * b)], a + 4 * b);
      ++count;
    }
  }
  return count;
}

// The children of one node, bounded: at most sixteen, held without allocating and without zeroing the
// sixteen slots (a search makes one of these per node it expands). take_best hands them out highest `key`
// first, ties in the order they were added (a stable sort's order), without sorting them: one integer per
// child (the key above the child's rank, 0 once taken), and each take is a branch-free maximum over them (a
// search often stops after the first few children).
template <typename Item, int Item::*key>
class SixteenChildren {
 public:
  void push_back(const Item& c) {
    rank_[size_] = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.*key)) + 1) << 4 | (15u - size_);
    slots_[size_++].item = c;
  }
  /// The best child not taken yet, or nullptr when every child was taken.
  const Item* take_best() {
    std::uint64_t best = 0;
    for (std::size_t k = 0; k < size_; ++k) best = std::max(best, rank_[k]);
    if (best == 0) return nullptr;
    const std::size_t slot = 15u - (best & 15u);
    rank_[slot] = 0;
    return &slots_[slot].item;
  }

 private:
  union Slot {
    Slot() {}  // left uninitialised: push_back writes a slot before anything reads it
    Item item;
  };
  std::array<Slot, 16> slots_;
  std::array<std::uint64_t, 16> rank_;  // (key + 1) << 4 | (15 - slot), 0 once taken; only [0, size_) written
  std::size_t size_ = 0;
};

struct Candidate {
  int rotation = 0;
  int i = 0, j = 0;
  int score = 0;   // Eq. 1 at depth 0, an upper bound above
  int bit = 0;     // child index a + 4 b within its parent
  int parent = 0;  // for the children of a root: the root's index
};

// Candidates a search skips (match_dmm_elsewhere): for each avoided pose, the translations within `radius`
// cells of its (i, j) at the rotations flagged near it.
struct Exclusion {
  struct Disc {
    std::vector<bool> near;  // per rotation of the query
    double i = 0, j = 0;     // [cells]
  };
  std::vector<Disc> discs;
  double radius = 0;     // [cells]
  double min_angle = 0;  // [rad]

  // Two poses are distinct when their translations lie min_distance [m] apart or their rotations differ by
  // more than min_angle [rad] (match_dmm_elsewhere, DmmSearch); throws InputError unless both are finite and
  // >= 0.
  Exclusion(double min_distance, double min_angle, double resolution)
      : radius(min_distance / resolution), min_angle(min_angle) {
    if (!(min_distance >= 0.0) || !std::isfinite(min_distance) || !(min_angle >= 0.0) ||
        !std::isfinite(min_angle))
      throw InputError("dmm: min_distance and min_angle must be finite and >= 0");
  }

  // The disc about translation (i, j) [cells], at the query's rotations within min_angle of theta.
  void add(const PreparedQuery& query, double i, double j, double theta) {
    Disc disc;
    disc.i = i, disc.j = j;
    for (const RotatedQuery& q : query.rotations)
      disc.near.push_back(std::abs(wrap_angle(q.angle - theta)) <= min_angle);
    discs.push_back(std::move(disc));
  }

  // True when every translation of the block of 4^d x 4^d at (i, j), depth d, of `rotation` is excluded: the
  // disc is convex, so the block lies inside it when its four corners do.
  bool covers(int rotation, int i, int j, int d) const {
    const int side = (1 << (2 * d)) - 1;
    const double r2 = radius * radius;
    const auto inside = [&](const Disc& disc) {
      if (!disc.near[static_cast<std::size_t>(rotation)]) return false;
      for (const int a : {0, side}) {
        for (const int b : {0, side}) {
          const double di = i + a - disc.i, dj = j + b - disc.j;
          if (di * di + dj * dj >= r2) return false;
        }
      }
      return true;
    };
    return std::any_of(discs.begin(), discs.end(), inside);
  }
};

// Depth-first branch-and-bound (Cartographer's FastCorrelativeScanMatcher2D::BranchAndBound), 16-way: a node
// at depth d is a block of 4^d x 4^d translations of one rotation; its sixteen children (depth d - 1) are
// bounded in one pass over the node's query cells with the packed pyramid level 2 (d - 1) (dmm_bounds.h).
// Depth-0 nodes are single translations, scored exactly. The roots (depth = search depth) tile the search
// range and are not bounded themselves. A node's cells are those of its parent that can score in it.
// Definitions: dmm_branch_and_bound.cc.
class BranchAndBound {
 public:
  BranchAndBound(const PreparedQuery& query, const PreparedMap& map, const std::vector<Range>& ranges,
                 int bar, const Exclusion* exclusion = nullptr)
      : query_(query),
        map_(map),
        ranges_(ranges),
        best_(Candidate{-1, 0, 0, bar, 0, 0}),
        exclusion_(exclusion) {}

  // Searches with candidates whose score does not exceed the bar pruned; returns the best candidate found
  // above the bar (rotation -1 when none).
  Candidate run() { return run_from(root_children()); }

  // The search from root children computed before (root_children), with bar raised to at least `bar`.
  Candidate run_from(const std::vector<Candidate>& candidates, int bar = -1);

  // The children of every root (the roots tile the search range and are not bounded themselves), bounded;
  // their values stay in root_values_ for descend.
  std::vector<Candidate> root_children();

  std::int64_t candidates_scored() const { return scored_; }

 private:
  struct Buffers {  // the cells of the node being expanded at one depth, and their looked-up values
    std::unique_ptr<int[]> x, y;
    std::unique_ptr<std::uint16_t[]> values;
  };

  bool excluded(const Candidate& c, int d) const {
    return exclusion_ != nullptr && exclusion_->covers(c.rotation, c.i, c.j, d);
  }

  CellList full_cells(int rotation) const {
    const RotatedQuery& r = query_.rotations[static_cast<std::size_t>(rotation)];
    return {r.x.data(), r.y.data(), r.x.size()};
  }

  // Bounds the children (at depth d - 1) of node c at depth d over `cells`, storing the looked-up values
  // when `values` is not null, and appends those inside the search range. Appends nothing when the pass
  // proved that no child beats `bar`.
  template <typename Out>
  void expand(const Candidate& c, int d, const CellList& cells, std::uint16_t* values, int bar, Out& out);

  using Children = SixteenChildren<Candidate, &Candidate::score>;

  // Node c at depth d (d = 0: a single translation); its parent (at depth d + 1) left its cells and values in
  // buffers_[d + 1], or in root_values_ for a root. Returns false when no sibling after c can beat the bar
  // either (siblings are visited best bound first).
  bool descend(const Candidate& c, int d);

  const PreparedQuery& query_;
  const PreparedMap& map_;
  const std::vector<Range>& ranges_;
  Candidate best_;
  const Exclusion* exclusion_;
  std::int64_t scored_ = 0;
  std::vector<Buffers> buffers_;                  // index: depth
  std::array<CellList, 16> lists_{};              // cells of the node being expanded at depth d
  std::unique_ptr<std::uint16_t[]> root_values_;  // per root, the values of its pass over the full cells
};

// match_dmm with a bar: only candidates scoring above `bar` are reported (exact = false otherwise), and none
// that `exclusion` (when given) excludes.
DmmResult match_dmm_above(const PreparedQuery& query, const PreparedMap& map, int bar,
                          const Exclusion* exclusion = nullptr);

}  // namespace partslam::dmm_internal
