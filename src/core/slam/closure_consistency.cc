#include "core/slam/closure_consistency.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <string>
#include <utility>

#include "core/error.h"
#include "core/parallel.h"

namespace partslam {
namespace {

// The cycle passes split the closures (in travel order) into this many chunks for the threads.
constexpr std::size_t kChunks = 64;

// The travel along the two chain segments of a and b's cycle [m].
double chain_travel(const Submaps& maps, const LoopClosure& a, const LoopClosure& b) {
  return std::abs(maps[a.match].travel - maps[b.match].travel) +
         std::abs(maps[a.query].travel - maps[b.query].travel);
}

}  // namespace

void validate(const ClosureConsistencyConfig& c) {
  const std::pair<double, const char*> values[] = {{c.offset, "offset"},
                                                   {c.rate, "rate"},
                                                   {c.turn, "turn"},
                                                   {c.turn_rate, "turn_rate"},
                                                   {c.max_chain, "max_chain"},
                                                   {c.long_chain, "long_chain"},
                                                   {c.long_factor, "long_factor"},
                                                   {c.long_min_confidence, "long_min_confidence"},
                                                   {c.long_alias_extent, "long_alias_extent"}};
  for (const auto& [v, name] : values)
    if (!(v >= 0) || !std::isfinite(v))
      throw InputError(std::string("closure consistency config: ") + name + " must be finite and >= 0");
}

namespace {

// The cycle of a and b through the chain of stored frames (a's closure back, the chain from a's match to b's, b's
// closure, the chain from b's query to a's): identity when both are right and the chain does not drift. Given the
// inverses it takes: of a's relative pose and of the frames of a's match and b's query.
Pose2 cycle_error(const Submaps& maps, const LoopClosure& a, const LoopClosure& b, const Pose2& a_inverse,
                  const Pose2& a_match_inverse, const Pose2& b_query_inverse) {
  return a_inverse * (a_match_inverse * maps[b.match].T_world_map) * b.T_match_query *
         (b_query_inverse * maps[a.query].T_world_map);
}

Pose2 cycle_error(const Submaps& maps, const LoopClosure& a, const LoopClosure& b) {
  return cycle_error(maps, a, b, a.T_match_query.inverse(), maps[a.match].T_world_map.inverse(),
                     maps[b.query].T_world_map.inverse());
}

// cycle_error over many pairs, with the inverses it takes computed once per submap and per closure.
class CycleErrors {
 public:
  CycleErrors(const Submaps& maps, const std::vector<LoopClosure>& closures) : maps_(maps) {
    for (const Submap& m : maps) map_world_.push_back(m.T_world_map.inverse());
    for (const LoopClosure& l : closures) query_match_.push_back(l.T_match_query.inverse());
  }
  /// cycle_error(maps, closures[x], closures[y]) for a = closures[x], b = closures[y].
  Pose2 operator()(std::size_t x, const LoopClosure& a, const LoopClosure& b) const {
    return cycle_error(maps_, a, b, query_match_[x], map_world_[a.match], map_world_[b.query]);
  }

 private:
  const Submaps& maps_;
  std::vector<Pose2> map_world_, query_match_;
};

bool within(const Pose2& E, double travel, double rate, const ClosureConsistencyConfig& c) {
  return E.translation().norm() <= c.offset + rate * travel && std::abs(E.theta) <= c.turn + c.turn_rate * travel;
}

}  // namespace

bool closures_agree(const Submaps& maps, const LoopClosure& a, const LoopClosure& b,
                    const ClosureConsistencyConfig& c) {
  return within(cycle_error(maps, a, b), chain_travel(maps, a, b), c.rate, c);
}

namespace {

// Greedy vertex cover of the disagreements: drop the closure with the most, the less confident first among
// equals (then the later one), until none are left; `kept` false on entry stays false.
void drop_conflicts(const std::vector<LoopClosure>& closures, const std::vector<std::vector<std::size_t>>& conflicts,
                    std::vector<bool>& kept) {
  const std::size_t n = closures.size();
  std::vector<std::size_t> degree(n);
  for (std::size_t k = 0; k < n; ++k) degree[k] = conflicts[k].size();
  const auto worse = [&](std::size_t x, std::size_t y) {  // x is dropped before y
    if (degree[x] != degree[y]) return degree[x] > degree[y];
    if (closures[x].confidence != closures[y].confidence)
      return closures[x].confidence < closures[y].confidence;
    return x > y;
  };
  const auto cmp = [&](std::size_t x, std::size_t y) { return worse(x, y); };
  std::set<std::size_t, decltype(cmp)> queue(cmp);
  for (std::size_t k = 0; k < n; ++k)
    if (degree[k] > 0) queue.insert(k);
  while (!queue.empty()) {
    const std::size_t k = *queue.begin();
    queue.erase(queue.begin());
    kept[k] = false;
    for (const std::size_t o : conflicts[k]) {
      if (!kept[o] || degree[o] == 0) continue;
      queue.erase(o);
      if (--degree[o] > 0) queue.insert(o);
    }
    degree[k] = 0;
  }
}

}  // namespace

std::vector<bool> consistent_closures(const Submaps& maps, const std::vector<LoopClosure>& closures,
                                      const ClosureConsistencyConfig& c, int num_threads) {
  validate(c);
  const std::size_t n = closures.size();
  for (const LoopClosure& l : closures)
    if (l.query >= maps.size() || l.match >= maps.size())
      throw InputError("closure consistency: a closure names a submap out of range");
  // Closures sorted by their query's travel, so that the pairs within a chain length are found in a window.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  const auto query_travel = [&](std::size_t k) { return maps[closures[k].query].travel; };
  const auto match_travel = [&](std::size_t k) { return maps[closures[k].match].travel; };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return query_travel(x) < query_travel(y); });
  // Each pair of closures still kept whose cycle's chain is longer than `shortest` and at most `longest`
  // (min_confidence: only closures at least this confident take part), visited as visit(chunk, x, y, E, travel):
  // the outer closures in kChunks chunks of the travel order, on num_threads; a chunk's visits are in the serial
  // order, so what each chunk collects, merged in chunk order, is what one thread would have collected.
  std::vector<bool> kept(n, true);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::size_t chunks = std::min<std::size_t>(n, kChunks);
  const CycleErrors cycle(maps, closures);
  const auto for_each_cycle = [&](double shortest, double longest, double min_confidence, auto&& visit) {
    parallel_for(chunks, num_threads, [&](std::size_t chunk) {
      for (std::size_t p = n * chunk / chunks; p < n * (chunk + 1) / chunks; ++p) {
        if (!kept[order[p]] || closures[order[p]].confidence < min_confidence) continue;
        const LoopClosure& a = closures[order[p]];
        for (std::size_t q = p + 1; q < n && query_travel(order[q]) - query_travel(order[p]) <= longest; ++q) {
          if (!kept[order[q]] || closures[order[q]].confidence < min_confidence) continue;
          const LoopClosure& b = closures[order[q]];
          const double travel = chain_travel(maps, a, b);
          if (travel > shortest && travel <= longest)
            visit(chunk, order[p], order[q], cycle(order[p], a, b), travel);
        }
      }
    });
  };
  // The pairs whose cycle breaks `rate`, per chunk, then each closure's list of those it disagrees with.
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> broken(chunks);
  std::vector<std::vector<std::size_t>> conflicts(n);
  const auto find_conflicts = [&](double shortest, double longest, double min_confidence, double rate) {
    for (auto& list : conflicts) list.clear();
    for_each_cycle(shortest, longest, min_confidence,
                   [&](std::size_t chunk, std::size_t x, std::size_t y, const Pose2& E, double travel) {
      if (!within(E, travel, rate, c)) broken[chunk].emplace_back(x, y);
    });
    for (auto& pairs : broken) {
      for (const auto& [x, y] : pairs) conflicts[x].push_back(y), conflicts[y].push_back(x);
      pairs.clear();
      pairs.shrink_to_fit();
    }
  };
  // The short cycles: the largest group that agrees within the fixed rate.
  find_conflicts(-1.0, c.max_chain, -kInf, c.rate);
  drop_conflicts(closures, conflicts, kept);
  if (!(c.long_chain > c.max_chain)) return kept;
  // The long cycles of that group's confident closures: its drift per metre of chain measured on them (the
  // median, from a histogram in bins of 1e-4 per metre, the last holding every larger one), and the cycles broken
  // by more than long_factor times it.
  constexpr double kBin = 1e-4;
  constexpr std::size_t kBins = 2001;
  std::vector<std::vector<std::size_t>> histograms(chunks, std::vector<std::size_t>(kBins, 0));
  for_each_cycle(c.max_chain, c.long_chain, c.long_min_confidence,
                 [&](std::size_t chunk, std::size_t, std::size_t, const Pose2& E, double travel) {
    const double bin = E.translation().norm() / travel / kBin;
    ++histograms[chunk][static_cast<std::size_t>(std::min(bin, static_cast<double>(kBins - 1)))];
  });
  std::vector<std::size_t> histogram(kBins, 0);
  for (const auto& h : histograms)
    for (std::size_t b = 0; b < kBins; ++b) histogram[b] += h[b];
  const std::size_t count = std::accumulate(histogram.begin(), histogram.end(), std::size_t{0});
  if (count == 0) return kept;
  std::size_t below = 0, median_bin = 0;
  while (median_bin + 1 < histogram.size() && 2 * (below + histogram[median_bin]) < count + 1)
    below += histogram[median_bin++];
  const double median = (static_cast<double>(median_bin) + 1) * kBin;
  const double long_rate = std::max(c.rate, c.long_factor * median);
  find_conflicts(c.max_chain, c.long_chain, c.long_min_confidence, long_rate);
  const std::vector<bool> before_long = kept;
  drop_conflicts(closures, conflicts, kept);
  // What was dropped, in stretches of the queries' travel (a gap over long_alias_extent starts a new one): a
  // stretch whose matches lie within long_alias_extent of each other saw one place as another (an alias) and stays
  // dropped; one whose matches are spread over the building disagrees with every place it revisits, which is the
  // front end's chain broken where no short cycle reaches (a heading lost), not an alias: it is kept.
  std::vector<std::size_t> dropped;
  for (const std::size_t k : order)
    if (before_long[k] && !kept[k]) dropped.push_back(k);
  for (std::size_t begin = 0, end = 0; begin < dropped.size(); begin = end) {
    double lo = match_travel(dropped[begin]), hi = lo;
    for (end = begin + 1; end < dropped.size() &&
                          query_travel(dropped[end]) - query_travel(dropped[end - 1]) <= c.long_alias_extent;
         ++end) {
      lo = std::min(lo, match_travel(dropped[end]));
      hi = std::max(hi, match_travel(dropped[end]));
    }
    if (hi - lo > c.long_alias_extent)
      for (std::size_t i = begin; i < end; ++i) kept[dropped[i]] = true;
  }
  return kept;
}

}  // namespace partslam
