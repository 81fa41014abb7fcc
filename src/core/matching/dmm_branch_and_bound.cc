// dMM's depth-first branch-and-bound (BranchAndBound, dmm_internal.h): match_dmm, match_dmm_elsewhere and
// match_dmm_many search one map with it, match_dmm_joint many.
// Tested by: core/matching/dmm_test.cc, core/matching/dmm_joint_test.cc
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/matching/dmm_bounds.h"
#include "core/matching/dmm_internal.h"

namespace partslam::dmm_internal {

template <typename Out>
void BranchAndBound::expand(const Candidate& c, int d, const CellList& cells, std::uint16_t* values, int bar,
                            Out& out) {
  scored_ += bound_children(map_.packed[static_cast<std::size_t>(d - 1)],
                            ranges_[static_cast<std::size_t>(c.rotation)], cells, c.i, c.j, bar, values,
                            [&](int i, int j, int bound, int bit) {
                              out.push_back({c.rotation, i, j, bound, bit, c.parent});
                            });
}

Candidate BranchAndBound::run_from(const std::vector<Candidate>& candidates, int bar) {
  best_.score = std::max(best_.score, bar);
  const int depth = static_cast<int>(map_.packed.size());
  // Best bound first (ties: generation order), popped lazily: most are never needed.
  std::vector<std::pair<Candidate, std::size_t>> heap;
  heap.reserve(candidates.size());
  for (std::size_t m = 0; m < candidates.size(); ++m) heap.emplace_back(candidates[m], m);
  const auto worse = [](const std::pair<Candidate, std::size_t>& a, const std::pair<Candidate, std::size_t>& b) {
    return a.first.score != b.first.score ? a.first.score < b.first.score : a.second > b.second;
  };
  std::make_heap(heap.begin(), heap.end(), worse);
  while (!heap.empty() && heap.front().first.score > best_.score) {
    std::pop_heap(heap.begin(), heap.end(), worse);
    Candidate c = heap.back().first;
    heap.pop_back();
    descend(c, depth - 1);
  }
  return best_;
}

std::vector<Candidate> BranchAndBound::root_children() {
  const int depth = static_cast<int>(map_.packed.size());
  const int block = 1 << (2 * depth);
  const std::size_t n = static_cast<std::size_t>(query_.num_points);
  buffers_.resize(static_cast<std::size_t>(depth));
  for (Buffers& b : buffers_) {
    b.x = std::make_unique_for_overwrite<int[]>(n + 8);
    b.y = std::make_unique_for_overwrite<int[]>(n + 8);
    b.values = std::make_unique_for_overwrite<std::uint16_t[]>(n + 8);
  }
  std::size_t roots = 0;
  for (const Range& r : ranges_) {
    if (!r.empty())
      roots += static_cast<std::size_t>(((r.i_hi - r.i_lo) / block + 1) * ((r.j_hi - r.j_lo) / block + 1));
  }
  root_values_ = std::make_unique_for_overwrite<std::uint16_t[]>(roots * n + 8);
  std::vector<Candidate> candidates;
  int root = 0;
  for (std::size_t k = 0; k < ranges_.size(); ++k) {
    const Range& r = ranges_[k];
    if (r.empty()) continue;
    for (int j = r.j_lo; j <= r.j_hi; j += block) {
      for (int i = r.i_lo; i <= r.i_hi; i += block, ++root) {
        const Candidate c{static_cast<int>(k), i, j, 0, 0, root};
        expand(c, depth, full_cells(c.rotation), root_values_.get() + static_cast<std::size_t>(root) * n,
               /*bar=*/-1, candidates);
      }
    }
  }
  return candidates;
}

bool BranchAndBound::descend(const Candidate& c, int d) {
  if (c.score <= best_.score) return false;
  if (excluded(c, d)) return true;
  if (d == 0) {
    best_ = c;
    return false;  // the siblings after c score no more than c
  }
  const auto depth = static_cast<int>(buffers_.size());
  // This node's cells: its parent's cells that can score in it (exactly c.score of them). Filtering
  // pays only when it drops at least half of them.
  CellList parent;
  const std::uint16_t* parent_values = nullptr;
  if (d + 1 == depth) {
    parent = full_cells(c.rotation);
    parent_values = root_values_.get() + static_cast<std::size_t>(c.parent) * parent.size;
  } else {
    parent = lists_[static_cast<std::size_t>(d + 1)];
    parent_values = buffers_[static_cast<std::size_t>(d + 1)].values.get();
  }
  Buffers& mine = buffers_[static_cast<std::size_t>(d)];
  CellList& list = lists_[static_cast<std::size_t>(d)];
  if (static_cast<std::size_t>(c.score) * 2 < parent.size) {
    list = {mine.x.get(), mine.y.get(), filter_cells(parent, parent_values, c.bit, mine.x.get(), mine.y.get())};
  } else {
    list = parent;
  }
  Children children;
  // Children at depth 0 are leaves: their values are not needed.
  expand(c, d, list, d > 1 ? mine.values.get() : nullptr, best_.score, children);
  while (const Candidate* child = children.take_best()) {
    if (!descend(*child, d - 1)) break;
  }
  return true;
}

DmmResult match_dmm_above(const PreparedQuery& query, const PreparedMap& map, int bar,
                          const Exclusion* exclusion) {
  check_compatible(query, map);
  const DmmConfig& config = map.config;
  const std::vector<Range> ranges = search_ranges(query, map);
  BranchAndBound search(query, map, ranges, bar, exclusion);
  const Candidate best = search.run();
  DmmResult result;
  if (best.rotation >= 0) {
    result = make_result(query, config, best.score, best.rotation, best.i, best.j);
  } else if (bar >= 0) {
    result.exact = false;
  }
  result.candidates_scored = search.candidates_scored();
  return result;
}

}  // namespace partslam::dmm_internal
