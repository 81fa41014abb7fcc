// DmmSearch (dmm.h): the distinct best poses of one query on one map, by one best-first branch-and-bound.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/matching/dmm.h"
#include "core/matching/dmm_bounds.h"
#include "core/matching/dmm_internal.h"

namespace partslam {

// Best-first enumeration (one queue of nodes over every rotation, highest bound first), so that each next
// pose costs only the nodes no earlier call bounded. Nodes above kSubtreeDepth are expanded into the queue,
// their query cells and looked-up values kept for their children (a node's cells are its parent's that can
// score in it: filter_cells, as in the depth-first search). A node at or below it (at most 16 x 16
// translations) is searched depth-first for its best leaf not yet excluded (lazy: one that reaches the best
// leaf pushed so far in this call); the leaf goes on the queue and so does the node again, bounded by that
// leaf, to yield its next best once the leaf is taken (lazy, none found: the node again, bounded by the bar).
// A leaf popped within the exclusion of a pose returned before is dropped, and so is a node wholly inside one
// (the disc is convex: its four corners).
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

  State(const PreparedQuery& q, const PreparedMap& m, double min_distance, double min_angle, bool lazy_search)
      : lazy(lazy_search),
        query(q),
        map(m),
        ranges(dmm_internal::search_ranges(q, m)),
        n(static_cast<std::size_t>(q.num_points)),
        queue(max_cells(q), static_cast<int>(m.packed.size()) + 1),
        returned(min_distance, min_angle, m.config.resolution) {
    for (Storage& level : scratch) {
      level = {std::make_unique_for_overwrite<int[]>(n + 8), std::make_unique_for_overwrite<int[]>(n + 8),
               std::make_unique_for_overwrite<std::uint16_t[]>(n + 8)};
    }
  }

  const bool lazy;
  const PreparedQuery& query;
  const PreparedMap& map;
  const std::vector<dmm_internal::Range> ranges;
  const std::size_t n;
  std::array<Storage, kSubtreeDepth + 1> scratch;  // per depth: the cells (and values) of a subtree's node
  Queue queue;
  std::vector<List> lists;
  std::vector<Storage> storage;
  dmm_internal::Exclusion returned;  // about every pose returned so far
  bool started = false;
  int floor = -1;  // the highest bar so far: nodes bounded at or below it are never pushed
  int best_pushed = -1;  // lazy: the best leaf pushed during this call to next()
  bool paused = false;   // the last call to next() ran out of its budget
  std::int64_t scored = 0;
  // A budget's unit, about proportional to time: the query cells the bound passes read, plus kPopWork per node
  // popped (its cells filtered and stored, the queue; fitted on freiburg-campus's and fhw's searches, where a
  // node popped cost about as much as 2000 cells read: 1.1 ms per million cells, 2.2 ms per thousand nodes).
  static constexpr std::int64_t kPopWork = 2000;
  std::int64_t work = 0;

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
    work += static_cast<std::int64_t>(cells.size);
    scored += dmm_internal::bound_children(map.packed[static_cast<std::size_t>(c.depth - 1)],
                                           ranges[static_cast<std::size_t>(c.rotation)], cells, c.i, c.j, bar,
                                           values, [&](int i, int j, int bound, int bit) {
                                             if (bound > bar)
                                               out.push_back({bound, c.depth - 1, c.rotation, i, j, bit, list});
                                           });
  }

  using Children = dmm_internal::SixteenChildren<Node, &Node::bound>;
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
      const dmm_internal::Range& r = ranges[k];
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
      // Lazy: this call's answer scores at least the best leaf pushed during it, so a leaf below that is not
      // needed yet: the subtree is searched for one that reaches it, and when none does, the node goes back on
      // the queue bounded by the bar (every leaf in it scores no more), to be searched again if a later call
      // gets down to it. Without the bar a node popped early spends a whole search on a leaf far below the
      // answer: 50 000 bounds for fr079's first pose against 4 400 with it (BM_DmmNextBest).
      const int bar = lazy ? std::max(floor, best_pushed - 1) : floor;
      Node best{bar, -1, 0, 0, 0, 0, 0};
      best_leaf(c, node_cells(c, parent, scratch[static_cast<std::size_t>(c.depth)]), best);
      if (best.depth < 0) {
        if (bar > floor) {
          Node later = c;
          later.bound = bar;
          queue.push(later);
        }
        return;  // nothing left in it
      }
      best_pushed = std::max(best_pushed, best.bound);
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

  DmmResult next(int bar, std::int64_t budget) {
    floor = std::max(floor, bar);
    if (!started) start();
    const std::int64_t scored_before = scored, work_before = work;
    if (!paused) best_pushed = -1;  // a call that goes on after a pause is still the same call
    paused = false;
    DmmResult result;
    while (!queue.empty() && queue.top_bound() > floor) {
      if (budget > 0 && work - work_before >= budget) {
        paused = true;  // between two pops: the next call pops the same queue
        result.paused = true;
        result.candidates_scored = scored - scored_before;
        return result;
      }
      const Node c = queue.pop();
      work += kPopWork;
      if (excluded(c)) continue;
      if (c.depth > 0) {
        pop_into(c);
        continue;
      }
      result = dmm_internal::make_result(query, map.config, c.bound, c.rotation, c.i, c.j);
      returned.add(query, c.i, c.j, result.T_map_query.theta);
      result.candidates_scored = scored - scored_before;
      return result;
    }
    if (floor >= 0) result.exact = false;
    result.candidates_scored = scored - scored_before;
    return result;
  }
};

DmmSearch::DmmSearch(const PreparedQuery& query, const PreparedMap& map, double min_distance, double min_angle,
                     bool lazy) {
  dmm_internal::check_compatible(query, map);
  state_ = std::make_unique<State>(query, map, min_distance, min_angle, lazy);
}

DmmSearch::~DmmSearch() = default;

DmmResult DmmSearch::next(int bar, std::int64_t budget) { return state_->next(bar, budget); }

}  // namespace partslam
