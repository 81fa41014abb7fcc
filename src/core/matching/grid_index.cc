#include "core/matching/grid_index.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <queue>
#include <string>

#include "core/error.h"

namespace partslam {

namespace {

int common(const GridBits& a, const GridBits& b) {
  return std::popcount(a.words[0] & b.words[0]) + std::popcount(a.words[1] & b.words[1]);
}
int either(const GridBits& a, const GridBits& b) {
  return std::popcount(a.words[0] | b.words[0]) + std::popcount(a.words[1] | b.words[1]);
}
GridBits operator|(const GridBits& a, const GridBits& b) {
  return GridBits{{a.words[0] | b.words[0], a.words[1] | b.words[1]}};
}
GridBits operator&(const GridBits& a, const GridBits& b) {
  return GridBits{{a.words[0] & b.words[0], a.words[1] & b.words[1]}};
}

// The upper bound on J(q, g) of the header, for a query side (grids with union qu, intersection qi and counts
// a_min..a_max) and a stored side (grids with union su, intersection si, counts b_min..b_max); the same
// correctly rounded division as the exact score, so bound >= score holds in floating point too.
double jaccard_bound(const GridBits& qu, const GridBits& qi, int a_min, int a_max, const GridBits& su,
                     const GridBits& si, int b_min, int b_max) {
  const int c_max = std::min({common(qu, su), a_max, b_max});
  const int u_min = std::max({either(qi, si), a_min, b_min, a_min + b_min - c_max, 1});
  return static_cast<double>(c_max) / u_min;
}

// Worst-first order of the running top k: a worse match has a lower score, or the same score and a higher index.
struct Worse {
  bool operator()(const GridMatch& a, const GridMatch& b) const {
    return a.score != b.score ? a.score > b.score : a.index < b.index;
  }
};
bool better(const GridMatch& a, const GridMatch& b) { return Worse{}(a, b); }

class TopK {
 public:
  explicit TopK(std::size_t k) : k_(k) {}
  bool full() const { return heap_.size() == k_; }
  // The score a bound must reach for anything it covers to enter (-inf until full). A bound equal to it may
  // still tie and win on index, so only bounds below it are pruned.
  double bar() const { return full() ? heap_.top().score : -std::numeric_limits<double>::infinity(); }
  void offer(const GridMatch& m) {
    if (k_ == 0) return;
    if (!full()) {
      heap_.push(m);
    } else if (better(m, heap_.top())) {
      heap_.pop();
      heap_.push(m);
    }
  }
  std::vector<GridMatch> sorted() && {
    std::vector<GridMatch> out;
    while (!heap_.empty()) out.push_back(heap_.top()), heap_.pop();
    std::reverse(out.begin(), out.end());
    return out;
  }

 private:
  std::size_t k_;
  std::priority_queue<GridMatch, std::vector<GridMatch>, Worse> heap_;
};

}  // namespace

GridQuery::GridQuery(std::vector<GridBits> grids, const GridConfig& config, int group_side)
    : grids_(std::move(grids)), counts_(grid_counts(grids_)) {
  validate(config);
  if (group_side < 1) throw InputError("grid index: group_side must be >= 1, got " + std::to_string(group_side));
  const int shifts = 2 * config.max_shift * config.substeps + 1;
  if (grids_.size() != static_cast<std::size_t>(4 * shifts * shifts))
    throw InputError("grid index: the query has " + std::to_string(grids_.size()) + " grids, the config's poses are " +
                     std::to_string(4 * shifts * shifts));
  for (int k = 0; k < 4; ++k)
    for (int y0 = 0; y0 < shifts; y0 += group_side)
      for (int x0 = 0; x0 < shifts; x0 += group_side) {
        Group g;
        g.all_common = GridBits{{~std::uint64_t{0}, ~std::uint64_t{0}}};
        g.min_count = std::numeric_limits<int>::max();
        for (int y = y0; y < std::min(shifts, y0 + group_side); ++y)
          for (int x = x0; x < std::min(shifts, x0 + group_side); ++x) {
            const auto v = static_cast<std::uint32_t>((k * shifts + y) * shifts + x);
            g.poses.push_back(v);
            g.all_union = g.all_union | grids_[v];
            g.all_common = g.all_common & grids_[v];
            g.min_count = std::min(g.min_count, counts_[v]);
            g.max_count = std::max(g.max_count, counts_[v]);
          }
        groups_.push_back(std::move(g));
      }
}

void validate(const GridIndexConfig& config) {
  if (config.leaf_size < 1 || config.leaf_size > 65536)
    throw InputError("grid index: leaf_size must be in [1, 65536], got " + std::to_string(config.leaf_size));
}

GridIndex::GridIndex(std::vector<GridBits> grids, std::vector<double> mu, double hub_weight,
                     const GridIndexConfig& config)
    : hub_weight_(hub_weight) {
  validate(config);
  if (!mu.empty() && mu.size() != grids.size())
    throw InputError("grid index: " + std::to_string(mu.size()) + " hubness values for " +
                     std::to_string(grids.size()) + " grids");
  if (grids.size() >= std::numeric_limits<std::uint32_t>::max())
    throw InputError("grid index: at most 2^32 - 2 maps, got " + std::to_string(grids.size()));
  if (!std::isfinite(hub_weight) || hub_weight < 0) throw InputError("grid index: hub_weight must be finite, >= 0");
  for (double m : mu)
    if (!std::isfinite(m)) throw InputError("grid index: a hubness value is not finite");
  if (mu.empty()) mu.assign(grids.size(), 0.0);
  index_.resize(grids.size());
  for (std::size_t i = 0; i < grids.size(); ++i) index_[i] = static_cast<std::uint32_t>(i);
  grids_ = std::move(grids);
  mu_ = std::move(mu);
  if (!grids_.empty()) build(0, static_cast<std::uint32_t>(grids_.size()), config);
  // Storage order: the maps of each leaf side by side.
  std::vector<GridBits> sorted_grids(grids_.size());
  std::vector<double> sorted_mu(mu_.size());
  for (std::size_t p = 0; p < index_.size(); ++p) sorted_grids[p] = grids_[index_[p]], sorted_mu[p] = mu_[index_[p]];
  grids_ = std::move(sorted_grids);
  mu_ = std::move(sorted_mu);
}

// Builds the node over index_[begin, end) (maps still in input order in grids_ / mu_) and returns its number.
std::int32_t GridIndex::build(std::uint32_t begin, std::uint32_t end, const GridIndexConfig& config) {
  Node node;
  node.begin = begin;
  node.end = end;
  node.all_common = GridBits{{~std::uint64_t{0}, ~std::uint64_t{0}}};
  node.min_count = 255;
  node.min_mu = std::numeric_limits<double>::infinity();
  for (std::uint32_t p = begin; p < end; ++p) {
    const GridBits& g = grids_[index_[p]];
    node.all_union = node.all_union | g;
    node.all_common = node.all_common & g;
    const int c = g.count();
    node.min_count = static_cast<std::uint8_t>(std::min<int>(node.min_count, c));
    node.max_count = static_cast<std::uint8_t>(std::max<int>(node.max_count, c));
    node.min_mu = std::min(node.min_mu, mu_[index_[p]]);
  }
  const auto id = static_cast<std::int32_t>(nodes_.size());
  nodes_.push_back(node);
  const std::uint32_t n = end - begin;
  if (n <= static_cast<std::uint32_t>(config.leaf_size)) return id;

  // Two far-apart pivots (the map least like the first, then the map least like that one); each map goes with
  // the pivot it is more like, so a node's maps resemble one another and its union and intersection stay tight.
  auto least_like = [&](const GridBits& from) {
    std::uint32_t best = begin;
    long best_both = 2, best_all = 1;  // similarity both / all, starting above any
    for (std::uint32_t p = begin; p < end; ++p) {
      const GridBits& g = grids_[index_[p]];
      const long both = common(from, g), all = std::max(either(from, g), 1);
      if (both * best_all < best_both * all) best = p, best_both = both, best_all = all;
    }
    return grids_[index_[best]];
  };
  const GridBits a = least_like(grids_[index_[begin]]);
  const GridBits b = least_like(a);
  auto nearer_a = [&](std::uint32_t i) {
    const GridBits& g = grids_[i];
    const long both_a = common(a, g), all_a = std::max(either(a, g), 1);
    const long both_b = common(b, g), all_b = std::max(either(b, g), 1);
    return both_a * all_b >= both_b * all_a;
  };
  const auto* first = index_.data() + begin;
  auto* mid = std::stable_partition(index_.data() + begin, index_.data() + end, nearer_a);
  std::uint32_t middle = static_cast<std::uint32_t>(mid - first) + begin;
  if (middle == begin || middle == end) middle = begin + n / 2;  // all alike: halves in input order
  const std::int32_t left = build(begin, middle, config);
  const std::int32_t right = build(middle, end, config);
  nodes_[static_cast<std::size_t>(id)].left = left;
  nodes_[static_cast<std::size_t>(id)].right = right;
  return id;
}

std::size_t GridIndex::memory_bytes() const {
  return grids_.size() * sizeof(GridBits) + mu_.size() * sizeof(double) + index_.size() * sizeof(std::uint32_t) +
         nodes_.size() * sizeof(Node);
}

std::vector<GridMatch> GridIndex::top_k(const GridQuery& query, std::size_t k, GridSearchStats* stats) const {
  GridSearchStats local;
  GridSearchStats& st = stats != nullptr ? *stats : local;
  TopK top(std::min(k, grids_.size()));
  if (nodes_.empty() || k == 0) return std::move(top).sorted();
  const auto& groups = query.groups();
  const auto& qgrids = query.grids();
  const auto& qcounts = query.counts();

  // The best bound over the query's poses for stored grids with union su, intersection si and counts
  // b_min..b_max, minus `hub`: each pose group's bound first; a group that can still reach the bar is refined
  // to its poses' own bounds. For one map (su = si = g) a pose's bound is its exact Jaccard, so the result is
  // the map's exact score whenever it reaches the bar (its best pose lies in a refined group); below the bar it
  // is only a bound, and the map cannot enter either way.
  auto best_bound = [&](const GridBits& su, const GridBits& si, int b_min, int b_max, double hub, bool refine) {
    const double bar = top.bar();
    double best = -std::numeric_limits<double>::infinity();
    for (const GridQuery::Group& g : groups) {
      const double group_bound =
          jaccard_bound(g.all_union, g.all_common, g.min_count, g.max_count, su, si, b_min, b_max) - hub;
      if (group_bound < bar || !refine) {
        best = std::max(best, group_bound);
        continue;
      }
      for (std::uint32_t v : g.poses)
        best = std::max(best, jaccard_bound(qgrids[v], qgrids[v], qcounts[v], qcounts[v], su, si, b_min, b_max) - hub);
      st.poses_scored += g.poses.size();
    }
    return best;
  };
  auto node_bound = [&](const Node& node) {
    ++st.nodes_visited;
    // Group bounds only: refining a node to its poses costs as much as scoring one map and prunes little more
    // (docs/NOTES.md).
    return best_bound(node.all_union, node.all_common, node.min_count, node.max_count, hub_weight_ * node.min_mu,
                      false);
  };
  auto score_map = [&](std::uint32_t p) {
    ++st.maps_scored;
    const GridBits& g = grids_[p];
    const int nb = g.count();
    top.offer({index_[p], best_bound(g, g, nb, nb, hub_weight_ * mu_[p], true)});
  };

  using Entry = std::pair<double, std::int32_t>;  // (bound, node): the highest bound first
  std::priority_queue<Entry> queue;
  queue.push({node_bound(nodes_[0]), 0});
  while (!queue.empty()) {
    const auto [bound, id] = queue.top();
    queue.pop();
    if (bound < top.bar()) break;  // nothing left can enter
    const Node& node = nodes_[static_cast<std::size_t>(id)];
    if (node.left < 0) {
      for (std::uint32_t p = node.begin; p < node.end; ++p) score_map(p);
      continue;
    }
    for (std::int32_t child : {node.left, node.right}) {
      const double b = node_bound(nodes_[static_cast<std::size_t>(child)]);
      if (b >= top.bar()) queue.push({b, child});
    }
  }
  return std::move(top).sorted();
}

std::vector<GridMatch> scan_top_k(const GridQuery& query, const std::vector<GridBits>& grids,
                                  const std::vector<double>& mu, double hub_weight, std::size_t k) {
  TopK top(std::min(k, grids.size()));
  for (std::size_t i = 0; i < grids.size(); ++i)
    top.offer({i, grid_similarity(query.grids(), query.counts(), grids[i]) -
                      hub_weight * (mu.empty() ? 0.0 : mu[i])});
  return std::move(top).sorted();
}

}  // namespace partslam
