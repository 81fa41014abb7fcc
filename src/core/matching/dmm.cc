#include "core/matching/dmm.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <queue>
#include <set>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "core/maps/scan.h"
#include "core/matching/dmm_bounds.h"

namespace partslam {
namespace {

constexpr double kPi = std::numbers::pi;

void require(bool ok, const std::string& message) {
  if (!ok) throw InputError("dmm config: " + message);
}

// Auto step (Cartographer's FastCorrelativeScanMatcher2D): the farthest point moves by at most one cell.
double auto_angular_step(const Points2& points, double resolution) {
  double d_max = 0.0;
  for (const Vec2& p : points) d_max = std::max(d_max, p.norm());
  if (d_max <= resolution) return kPi / 4;
  return std::acos(std::clamp(1.0 - resolution * resolution / (2.0 * d_max * d_max), -1.0, 1.0));
}

std::vector<double> search_angles(const DmmConfig& config, double step) {
  std::vector<double> angles;
  if (config.canonical) {
    const int n = static_cast<int>(std::floor(config.angular_window / step + 1e-9));
    for (int base = 0; base < config.canonical_turns; ++base) {
      for (int m = -n; m <= n; ++m) angles.push_back(base * 2 * kPi / config.canonical_turns + m * step);
    }
    // A wing's walls and the local map's agree up to a quarter turn: four families each.
    const int extra = static_cast<int>(std::floor(config.extra_window / step + 1e-9));
    for (const double offset : config.extra_directions) {
      for (int base = 0; base < 4; ++base) {
        for (int m = -extra; m <= extra; ++m) angles.push_back(base * kPi / 2 + offset + m * step);
      }
    }
  } else {
    const int n = std::max(1, static_cast<int>(std::ceil(2 * kPi / step - 1e-9)));
    for (int m = 0; m < n; ++m) angles.push_back(m * (2 * kPi / n));
  }
  return angles;
}

// Translation range (in cells) searched for one rotation: the window intersected with the translations at
// which at least one rotated query cell lands on the target grid (all others score 0).
struct Range {
  int i_lo = 0, i_hi = -1, j_lo = 0, j_hi = -1;
  bool empty() const { return i_hi < i_lo || j_hi < j_lo; }
};

Range search_range(const RotatedQuery& r, const OccupancyGrid& grid, const DmmConfig& config) {
  Range range;
  if (r.x_max < r.x_min || grid.width == 0 || grid.height == 0) return range;
  range.i_lo = grid.x0 - r.x_max;
  range.i_hi = grid.x0 + grid.width - 1 - r.x_min;
  range.j_lo = grid.y0 - r.y_max;
  range.j_hi = grid.y0 + grid.height - 1 - r.y_min;
  if (config.linear_window > 0.0) {
    const int w = static_cast<int>(std::floor(config.linear_window / config.resolution + 1e-9));
    range.i_lo = std::max(range.i_lo, -w);
    range.i_hi = std::min(range.i_hi, w);
    range.j_lo = std::max(range.j_lo, -w);
    range.j_hi = std::min(range.j_hi, w);
  }
  return range;
}

// The query and the map were prepared with their own configs (validated then); they must share the lattice
// and the kind of rotation search. The map's config decides the translation window (its pyramid depth was
// chosen for it).
void check_compatible(const PreparedQuery& query, const PreparedMap& map) {
  const auto same = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(a, b); };
  if (!same(query.config.resolution, map.config.resolution)) {
    throw InputError("dmm: the query was prepared at " + std::to_string(query.config.resolution) +
                     " m, the map at " + std::to_string(map.config.resolution) + " m: resolutions differ");
  }
  if (query.config.canonical != map.config.canonical) {
    throw InputError("dmm: the query and the map disagree on canonical (Manhattan-frame) matching");
  }
}

DmmResult make_result(const PreparedQuery& query, const DmmConfig& config, int inliers, int rotation, int i, int j) {
  DmmResult result;
  result.inliers = inliers;
  result.inlier_fraction = query.num_points > 0 ? static_cast<double>(inliers) / query.num_points : 0.0;
  if (rotation >= 0) {
    result.T_map_query = {i * config.resolution, j * config.resolution,
                          wrap_angle(query.rotations[static_cast<std::size_t>(rotation)].angle)};
  }
  return result;
}

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

// Depth-first branch-and-bound (Cartographer's FastCorrelativeScanMatcher2D::BranchAndBound), 16-way: a node
// at depth d is a block of 4^d x 4^d translations of one rotation; its sixteen children (depth d - 1) are
// bounded in one pass over the node's query cells with the packed pyramid level 2 (d - 1) (dmm_bounds.h).
// Depth-0 nodes are single translations, scored exactly. The roots (depth = search depth) tile the search
// range and are not bounded themselves. A node's cells are those of its parent that can score in it.
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

class BranchAndBound {
 public:
  BranchAndBound(const PreparedQuery& query, const PreparedMap& map, const std::vector<Range>& ranges, int bar,
                 const Exclusion* exclusion = nullptr)
      : query_(query), map_(map), ranges_(ranges), best_(Candidate{-1, 0, 0, bar, 0, 0}), exclusion_(exclusion) {}

  // Searches with candidates whose score does not exceed the bar pruned; returns the best candidate found
  // above the bar (rotation -1 when none).
  Candidate run() { return run_from(root_children()); }

  // The search from root children computed before (root_children), with bar raised to at least `bar`.
  Candidate run_from(const std::vector<Candidate>& candidates, int bar = -1) {
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

  // The children of every root (the roots tile the search range and are not bounded themselves), bounded; their
  // values stay in root_values_ for descend.
  std::vector<Candidate> root_children() {
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
      if (!r.empty()) roots += static_cast<std::size_t>(((r.i_hi - r.i_lo) / block + 1) * ((r.j_hi - r.j_lo) / block + 1));
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
  void expand(const Candidate& c, int d, const CellList& cells, std::uint16_t* values, int bar, Out& out) {
    scored_ += bound_children(map_.packed[static_cast<std::size_t>(d - 1)],
                              ranges_[static_cast<std::size_t>(c.rotation)], cells, c.i, c.j, bar, values,
                              [&](int i, int j, int bound, int bit) {
                                out.push_back({c.rotation, i, j, bound, bit, c.parent});
                              });
  }

  using Children = SixteenChildren<Candidate, &Candidate::score>;

  // Node c at depth d (d = 0: a single translation); its parent (at depth d + 1) left its cells and values in
  // buffers_[d + 1], or in root_values_ for a root. Returns false when no sibling after c can beat the bar
  // either (siblings are visited best bound first).
  bool descend(const Candidate& c, int d) {
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

  const PreparedQuery& query_;
  const PreparedMap& map_;
  const std::vector<Range>& ranges_;
  Candidate best_;
  const Exclusion* exclusion_;
  std::int64_t scored_ = 0;
  std::vector<Buffers> buffers_;              // index: depth
  std::array<CellList, 16> lists_{};          // cells of the node being expanded at depth d
  std::unique_ptr<std::uint16_t[]> root_values_;  // per root, the values of its pass over the full cells
};

std::vector<Range> search_ranges(const PreparedQuery& query, const PreparedMap& map) {
  std::vector<Range> ranges;
  ranges.reserve(query.rotations.size());
  for (const RotatedQuery& r : query.rotations) ranges.push_back(search_range(r, map.grid, map.config));
  return ranges;
}

// match_dmm with a bar: only candidates scoring above `bar` are reported (exact = false otherwise), and none
// that `exclusion` (when given) excludes.
DmmResult match_dmm_above(const PreparedQuery& query, const PreparedMap& map, int bar,
                          const Exclusion* exclusion = nullptr) {
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

}  // namespace

void validate(const DmmConfig& c) {
  require(c.resolution > 0.0 && std::isfinite(c.resolution),
          "resolution must be a positive finite number, got " + std::to_string(c.resolution));
  require(std::isfinite(c.linear_window), "linear_window must be finite (<= 0 means the whole target map)");
  require(c.linear_window / c.resolution <= 1e6, "linear_window / resolution is absurdly large");
  require(c.angular_window >= 0.0 && c.angular_window <= kPi / 4,
          "angular_window must be in [0, pi/4] rad, got " + std::to_string(c.angular_window));
  require(c.angular_step >= 0.0 && c.angular_step <= kPi / 2 && std::isfinite(c.angular_step),
          "angular_step must be in [0, pi/2] rad (0: automatic), got " + std::to_string(c.angular_step));
  require(c.angular_step == 0.0 || c.angular_step >= 1e-5, "angular_step must be 0 (automatic) or >= 1e-5 rad");
  require(c.canonical_turns == 4 || c.canonical_turns == 8,
          "canonical_turns must be 4 or 8, got " + std::to_string(c.canonical_turns));
  require(c.extra_directions.size() <= 8, "extra_directions: at most 8, got " + std::to_string(c.extra_directions.size()));
  for (const double d : c.extra_directions)
    require(std::abs(d) <= kPi / 4, "extra_directions must each be in [-pi/4, pi/4] rad, got " + std::to_string(d));
  require(c.extra_window >= 0.0 && c.extra_window <= kPi / 4,
          "extra_window must be in [0, pi/4] rad, got " + std::to_string(c.extra_window));
  require(c.dilation >= 0 && c.dilation <= 100, "dilation must be in [0, 100] cells, got " + std::to_string(c.dilation));
  require(c.search_depth >= 0 && c.search_depth <= 8,
          "search_depth must be in [0, 8] (0: automatic), got " + std::to_string(c.search_depth));
}

DmmConfig dmm_config_for_dictionary() {
  DmmConfig config;
  config.linear_window = 0.0;
  return config;
}

namespace {

// Refuses points spread over more than kMaxMapExtent: a map's grid pyramid grows with its area, and a query's
// rotation step shrinks with its extent (docs/NOTES.md has what a huge query cost without this check).
void check_extent(const Points2& points, const char* what) {
  if (const Box2 box = bounding_box(points); box.width() > kMaxMapExtent || box.height() > kMaxMapExtent) {
    char text[160];
    std::snprintf(text, sizeof text, "dMM: the %s's points span %.0f x %.0f m, more than the %.0f m limit "
                  "(a stray scan far from the rest?)", what, box.width(), box.height(), kMaxMapExtent);
    throw InputError(text);
  }
}

}  // namespace

PreparedQuery prepare_query(const Points2& points_query, const DmmConfig& config) {
  validate(config);
  for (const Vec2& p : points_query) {
    if (!p.allFinite() || p.norm() > 1e6) throw InputError("dmm: query point coordinates must be finite and < 1e6 m");
  }
  check_extent(points_query, "query");
  PreparedQuery query;
  query.config = config;
  query.resolution = config.resolution;
  query.num_points = static_cast<int>(points_query.size());
  query.angular_step = config.angular_step > 0.0 ? config.angular_step
                                                   : auto_angular_step(points_query, config.resolution);
  for (const double angle : search_angles(config, query.angular_step)) {
    RotatedQuery r;
    r.angle = angle;
    const double c = std::cos(angle), s = std::sin(angle);
    r.x.reserve(points_query.size());
    r.y.reserve(points_query.size());
    // Cells sorted by row (a stable counting sort), so that the search skips rows off the grid.
    std::vector<int> xs, ys;
    xs.reserve(points_query.size());
    ys.reserve(points_query.size());
    for (const Vec2& p : points_query) {
      xs.push_back(static_cast<int>(std::floor((c * p.x() - s * p.y()) / config.resolution)));
      ys.push_back(static_cast<int>(std::floor((s * p.x() + c * p.y()) / config.resolution)));
    }
    if (!ys.empty()) {
      const auto [y_lo, y_hi] = std::minmax_element(ys.begin(), ys.end());
      const int y0 = *y_lo;
      std::vector<int> start(static_cast<std::size_t>(*y_hi - y0) + 2, 0);
      for (const int y : ys) ++start[static_cast<std::size_t>(y - y0) + 1];
      for (std::size_t m = 1; m < start.size(); ++m) start[m] += start[m - 1];
      r.x.resize(xs.size());
      r.y.resize(ys.size());
      for (std::size_t k = 0; k < xs.size(); ++k) {
        const auto slot = static_cast<std::size_t>(start[static_cast<std::size_t>(ys[k] - y0)]++);
        r.x[slot] = xs[k];
        r.y[slot] = ys[k];
      }
    }
    if (!r.x.empty()) {
      const auto [x_lo, x_hi] = std::minmax_element(r.x.begin(), r.x.end());
      const auto [y_lo, y_hi] = std::minmax_element(r.y.begin(), r.y.end());
      r.x_min = *x_lo, r.x_max = *x_hi, r.y_min = *y_lo, r.y_max = *y_hi;
    }
    query.rotations.push_back(std::move(r));
  }
  return query;
}

PreparedMap prepare_map(const Points2& points_map, const DmmConfig& config) {
  validate(config);
  check_extent(points_map, "map");
  PreparedMap map;
  map.config = config;
  map.num_points = static_cast<int>(points_map.size());
  const OccupancyGrid grid = build_occupancy_grid(points_map, config.resolution, config.dilation);
  int depth = config.search_depth;
  if (depth == 0) {
    // Root blocks of 4^depth cells: about 2 x 2 of them across the translation window (or the whole target).
    const int cells = config.linear_window > 0.0
                          ? 2 * static_cast<int>(std::floor(config.linear_window / config.resolution + 1e-9)) + 1
                          : std::max(grid.width, grid.height);
    depth = 1;
    while (depth < 8 && (1 << (2 * depth)) * 2 < cells) ++depth;
  }
  const GridPyramid pyramid = build_grid_pyramid(grid, 2 * depth - 1);
  for (int d = 0; d < depth; ++d) {
    map.packed.push_back(build_packed_level(pyramid.levels[static_cast<std::size_t>(2 * d)], 1 << (2 * d)));
  }
  map.grid = grid;
  return map;
}

DmmResult match_dmm(const PreparedQuery& query, const PreparedMap& map) { return match_dmm_above(query, map, -1); }

DmmResult match_dmm_elsewhere(const PreparedQuery& query, const PreparedMap& map, std::span<const Pose2> avoid,
                              double min_distance, double min_angle, int bar) {
  Exclusion exclusion(min_distance, min_angle, map.config.resolution);
  for (const Pose2& pose : avoid) {
    if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.theta))
      throw InputError("dmm: a pose to avoid must be finite");
    exclusion.add(query, pose.x / map.config.resolution, pose.y / map.config.resolution, pose.theta);
  }
  return match_dmm_above(query, map, bar, &exclusion);
}

DmmResult match_dmm_elsewhere(const PreparedQuery& query, const PreparedMap& map, const Pose2& avoid,
                              double min_distance, double min_angle) {
  return match_dmm_elsewhere(query, map, std::span<const Pose2>(&avoid, 1), min_distance, min_angle);
}

// Best-first enumeration (one queue of nodes over every rotation, highest bound first), so that each next
// pose costs only the nodes no earlier call bounded. Nodes above kSubtreeDepth are expanded into the queue,
// their query cells and looked-up values kept for their children (a node's cells are its parent's that can
// score in it: filter_cells, as in the depth-first search). A node at or below it (at most 16 x 16
// translations) is searched depth-first for its best leaf not yet excluded; the leaf goes on the queue and so
// does the node again, bounded by that leaf, to yield its next best once the leaf is taken. A leaf popped
// within the exclusion of a pose returned before is dropped, and so is a node wholly inside one (the disc is
// convex: its four corners).
struct DmmSearch::State {
  static constexpr int kSubtreeDepth = 2;
  struct Node {
    int bound = 0;  // Eq. 1 at depth 0, an upper bound above
    int depth = 0;
    int rotation = 0, i = 0, j = 0;
    int bit = 0;   // child index a + 4 b within its parent
    int list = 0;  // index into lists: the parent's cells and values
  };
  // The nodes to expand, popped highest bound first, then lowest depth (a leaf first: it ends the search),
  // then first pushed first. Bounds are Eq. 1 counts in [0, points], so a bucket per (bound, depth) holds
  // them in push order and a pop is a step down to the highest non-empty bound: no comparisons, no heap to
  // sift.
  class Queue {
   public:
    Queue(int max_bound, int depths)
        : depths_(depths),
          fifo_(static_cast<std::size_t>(max_bound + 1) * static_cast<std::size_t>(depths)),
          count_(static_cast<std::size_t>(max_bound + 1), 0) {}
    bool empty() const { return size_ == 0; }
    int top_bound() const { return top_; }  // valid when not empty
    void push(const Node& node) {
      if (node.bound < 0 || static_cast<std::size_t>(node.bound) >= count_.size() || node.depth < 0 ||
          node.depth >= depths_)
        throw std::logic_error("dmm: a node's bound or depth is outside the search queue");
      fifo(node.bound, node.depth).nodes.push_back(node);
      ++count_[static_cast<std::size_t>(node.bound)];
      top_ = size_++ == 0 ? node.bound : std::max(top_, node.bound);
    }
    Node pop() {  // not empty
      for (int d = 0;; ++d) {
        Fifo& f = fifo(top_, d);
        if (f.head == f.nodes.size()) continue;
        const Node node = f.nodes[f.head++];
        if (f.head == f.nodes.size()) f.nodes.clear(), f.head = 0;
        --count_[static_cast<std::size_t>(top_)], --size_;
        if (size_ > 0)
          while (count_[static_cast<std::size_t>(top_)] == 0) --top_;
        return node;
      }
    }

   private:
    struct Fifo {
      std::vector<Node> nodes;
      std::size_t head = 0;
    };
    Fifo& fifo(int bound, int depth) {
      return fifo_[static_cast<std::size_t>(bound) * static_cast<std::size_t>(depths_) +
                   static_cast<std::size_t>(depth)];
    }
    int depths_;
    std::vector<Fifo> fifo_;
    std::vector<std::size_t> count_;  // nodes per bound
    std::size_t size_ = 0;
    int top_ = 0;  // the highest non-empty bound (when not empty)
  };
  struct List {  // the cells of an expanded node and their looked-up values (at the level of its children)
    CellList cells;
    const std::uint16_t* values = nullptr;
  };
  struct Storage {
    std::unique_ptr<int[]> x, y;
    std::unique_ptr<std::uint16_t[]> values;
  };

  State(const PreparedQuery& q, const PreparedMap& m, double min_distance, double min_angle)
      : query(q),
        map(m),
        ranges(search_ranges(q, m)),
        n(static_cast<std::size_t>(q.num_points)),
        queue(max_cells(q), static_cast<int>(m.packed.size()) + 1),
        returned(min_distance, min_angle, m.config.resolution) {
    for (Storage& level : scratch) {
      level = {std::make_unique_for_overwrite<int[]>(n + 8), std::make_unique_for_overwrite<int[]>(n + 8),
               std::make_unique_for_overwrite<std::uint16_t[]>(n + 8)};
    }
  }

  const PreparedQuery& query;
  const PreparedMap& map;
  const std::vector<Range> ranges;
  const std::size_t n;
  std::array<Storage, kSubtreeDepth + 1> scratch;  // per depth: the cells (and values) of a subtree's node
  Queue queue;
  std::vector<List> lists;
  std::vector<Storage> storage;
  Exclusion returned;  // about every pose returned so far
  bool started = false;
  int floor = -1;  // the highest bar so far: nodes bounded at or below it are never pushed
  std::int64_t scored = 0;

  // The most query cells of any rotation: no bound exceeds it.
  static int max_cells(const PreparedQuery& q) {
    std::size_t most = 0;
    for (const RotatedQuery& r : q.rotations) most = std::max(most, r.x.size());
    return static_cast<int>(most);
  }

  bool excluded(const Node& c) const { return returned.covers(c.rotation, c.i, c.j, c.depth); }

  // The children of node c (at depth c.depth) over `cells`, bounded, those inside the search range that beat
  // `bar`; none when the pass proved that no child beats it. values: as child_bounds.
  template <typename Out>
  void children(const Node& c, const CellList& cells, int bar, std::uint16_t* values, int list, Out& out) {
    scored += bound_children(map.packed[static_cast<std::size_t>(c.depth - 1)],
                             ranges[static_cast<std::size_t>(c.rotation)], cells, c.i, c.j, bar, values,
                             [&](int i, int j, int bound, int bit) {
                               if (bound > bar)
                                 out.push_back({bound, c.depth - 1, c.rotation, i, j, bit, list});
                             });
  }

  using Children = SixteenChildren<Node, &Node::bound>;
  struct Pusher {
    State& state;
    void push_back(const Node& c) { state.queue.push(c); }
  };

  // Depth-first: the best leaf under node c (depth <= kSubtreeDepth, query cells `cells`) that beats best.bound
  // and is not excluded, into best.
  void best_leaf(const Node& c, const CellList& cells, Node& best) {
    Children kids;
    const int d = c.depth;
    std::uint16_t* values = d > 1 ? scratch[static_cast<std::size_t>(d)].values.get() : nullptr;
    children(c, cells, best.bound, values, -1, kids);
    // Highest bound first, ties in the pass's order.
    while (const Node* kid = kids.take_best()) {
      if (kid->bound <= best.bound) break;
      if (excluded(*kid)) continue;
      if (kid->depth == 0) {
        best = *kid;
        break;  // the rest score no more
      }
      best_leaf(*kid, node_cells(*kid, {cells, values}, scratch[static_cast<std::size_t>(kid->depth)]), best);
    }
  }

  // Filtering a node's cells out of its parent's pays only when it drops at least half of them (exactly
  // c.bound of them can score in it).
  static bool filters(const Node& c, const List& parent) {
    return static_cast<std::size_t>(c.bound) * 2 < parent.cells.size;
  }

  // Node c's query cells: those of its parent (cells with their values) that can score in it, into `room`
  // (room for c.bound cells); the parent's own when filtering would not pay.
  static CellList node_cells(const Node& c, const List& parent, Storage& room) {
    if (!filters(c, parent)) return parent.cells;
    return {room.x.get(), room.y.get(),
            filter_cells(parent.cells, parent.values, c.bit, room.x.get(), room.y.get())};
  }

  // The roots tile each rotation's range and are not bounded themselves: their children are.
  void start() {
    const int depth = static_cast<int>(map.packed.size());
    const int block = 1 << (2 * depth);
    for (std::size_t k = 0; k < ranges.size(); ++k) {
      const Range& r = ranges[k];
      if (r.empty()) continue;
      const RotatedQuery& rq = query.rotations[k];
      const CellList full{rq.x.data(), rq.y.data(), rq.x.size()};
      for (int j = r.j_lo; j <= r.j_hi; j += block) {
        for (int i = r.i_lo; i <= r.i_hi; i += block) {
          std::uint16_t* values = nullptr;
          if (depth > 1) {
            storage.push_back({nullptr, nullptr, std::make_unique_for_overwrite<std::uint16_t[]>(n + 8)});
            values = storage.back().values.get();
          }
          lists.push_back({full, values});
          Pusher pusher{*this};
          children({0, depth, static_cast<int>(k), i, j, 0, 0}, full, floor, values,
                   static_cast<int>(lists.size()) - 1, pusher);
        }
      }
    }
    started = true;
  }

  void pop_into(const Node& c) {
    const List& parent = lists[static_cast<std::size_t>(c.list)];
    if (c.depth <= kSubtreeDepth) {
      Node best{floor, -1, 0, 0, 0, 0, 0};
      best_leaf(c, node_cells(c, parent, scratch[static_cast<std::size_t>(c.depth)]), best);
      if (best.depth < 0) return;  // nothing left in it
      queue.push(best);
      Node again = c;  // its next best scores no more than this one
      again.bound = best.bound;
      queue.push(again);
      return;
    }
    Storage mine;
    if (filters(c, parent)) {
      mine.x = std::make_unique_for_overwrite<int[]>(static_cast<std::size_t>(c.bound) + 8);
      mine.y = std::make_unique_for_overwrite<int[]>(static_cast<std::size_t>(c.bound) + 8);
    }
    const CellList cells = node_cells(c, parent, mine);
    mine.values = std::make_unique_for_overwrite<std::uint16_t[]>(cells.size + 8);
    std::uint16_t* values = mine.values.get();
    lists.push_back({cells, values});
    storage.push_back(std::move(mine));
    Pusher pusher{*this};
    children(c, cells, floor, values, static_cast<int>(lists.size()) - 1, pusher);
  }

  DmmResult next(int bar) {
    floor = std::max(floor, bar);
    if (!started) start();
    const std::int64_t scored_before = scored;
    DmmResult result;
    while (!queue.empty() && queue.top_bound() > floor) {
      const Node c = queue.pop();
      if (excluded(c)) continue;
      if (c.depth > 0) {
        pop_into(c);
        continue;
      }
      result = make_result(query, map.config, c.bound, c.rotation, c.i, c.j);
      returned.add(query, c.i, c.j, result.T_map_query.theta);
      result.candidates_scored = scored - scored_before;
      return result;
    }
    if (floor >= 0) result.exact = false;
    result.candidates_scored = scored - scored_before;
    return result;
  }
};

DmmSearch::DmmSearch(const PreparedQuery& query, const PreparedMap& map, double min_distance, double min_angle) {
  check_compatible(query, map);
  state_ = std::make_unique<State>(query, map, min_distance, min_angle);
}

DmmSearch::~DmmSearch() = default;

DmmResult DmmSearch::next(int bar) { return state_->next(bar); }

std::vector<DmmResult> match_dmm_joint(const PreparedQuery& query, std::span<const PreparedMap* const> maps,
                                       int top_k) {
  if (top_k < 1) throw InputError("dmm: the joint search needs top_k >= 1, got " + std::to_string(top_k));
  for (const PreparedMap* m : maps) check_compatible(query, *m);
  const std::size_t n = maps.size();
  std::vector<std::vector<Range>> ranges(n);
  std::vector<std::unique_ptr<BranchAndBound>> searches;
  std::vector<std::vector<Candidate>> roots(n);
  std::vector<int> bound(n, -1);  // a map's bound: the best bound of its root children
  for (std::size_t m = 0; m < n; ++m) {
    ranges[m] = search_ranges(query, *maps[m]);
    searches.push_back(std::make_unique<BranchAndBound>(query, *maps[m], ranges[m], -1));
    roots[m] = searches.back()->root_children();
    for (const Candidate& c : roots[m]) bound[m] = std::max(bound[m], c.score);
  }
  // The maps best bound first (ties: the earlier map), each searched with the k-th best exact score so far as its
  // bar (raised by one for a map earlier than the k-th one's, which wins a tie); once a map's bound cannot beat the
  // bar, neither can any map after it.
  std::vector<std::size_t> order(n);
  for (std::size_t m = 0; m < n; ++m) order[m] = m;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return bound[a] > bound[b]; });
  std::set<std::pair<int, std::size_t>, std::function<bool(const std::pair<int, std::size_t>&,
                                                           const std::pair<int, std::size_t>&)>>
      top([](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first : a.second < b.second; });
  const auto bar_for = [&](std::size_t m) {
    if (top.size() < static_cast<std::size_t>(top_k)) return -1;
    const auto& [score, worst] = *top.rbegin();
    return m < worst ? score - 1 : score;
  };
  std::vector<DmmResult> results(n);
  std::vector<Candidate> best(n, Candidate{-1, 0, 0, -1, 0, 0});
  for (const std::size_t m : order) {
    if (top.size() == static_cast<std::size_t>(top_k) && bound[m] < top.rbegin()->first) break;
    const int bar = bar_for(m);
    if (bound[m] <= bar) continue;
    best[m] = searches[m]->run_from(roots[m], bar);
    if (best[m].rotation < 0) continue;  // nothing above the bar
    top.insert({best[m].score, m});
    if (top.size() > static_cast<std::size_t>(top_k)) top.erase(std::prev(top.end()));
  }
  for (std::size_t m = 0; m < n; ++m) {
    if (top.count({best[m].score, m})) {
      results[m] = make_result(query, maps[m]->config, best[m].score, best[m].rotation, best[m].i, best[m].j);
    } else {
      results[m].exact = false;
    }
    results[m].candidates_scored = searches[m]->candidates_scored();
  }
  return results;
}

DmmResult match_exhaustive(const PreparedQuery& query, const PreparedMap& map) {
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

std::vector<DmmResult> match_dmm_many(const PreparedQuery& query, std::span<const PreparedMap> maps, int top_k,
                                      int num_threads) {
  std::vector<const PreparedMap*> pointers;
  pointers.reserve(maps.size());
  for (const PreparedMap& m : maps) pointers.push_back(&m);
  return match_dmm_many(query, pointers, top_k, num_threads);
}

std::vector<DmmResult> match_dmm_many(const PreparedQuery& query, std::span<const PreparedMap* const> maps,
                                      int top_k, int num_threads) {
  for (const PreparedMap* m : maps) check_compatible(query, *m);  // once, before any thread starts
  if (num_threads < 1) throw InputError("dmm: num_threads must be >= 1, got " + std::to_string(num_threads));
  std::vector<DmmResult> results(maps.size());
  if (top_k <= 0) {
    const auto n = static_cast<std::ptrdiff_t>(maps.size());
#pragma omp parallel for schedule(dynamic) num_threads(num_threads) if (num_threads > 1)
    for (std::ptrdiff_t m = 0; m < n; ++m) {
      results[static_cast<std::size_t>(m)] = match_dmm(query, *maps[static_cast<std::size_t>(m)]);
    }
    return results;
  }
  // Min-heap of the k best exact scores so far; its top is the bar a new map must beat.
  std::priority_queue<int, std::vector<int>, std::greater<>> best;
  for (std::size_t m = 0; m < maps.size(); ++m) {
    const int bar = static_cast<int>(best.size()) == top_k ? best.top() : -1;
    results[m] = match_dmm_above(query, *maps[m], bar);
    if (!results[m].exact) continue;
    best.push(results[m].inliers);
    if (static_cast<int>(best.size()) > top_k) best.pop();
  }
  return results;
}

}  // namespace partslam
