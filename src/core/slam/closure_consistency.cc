#include "core/slam/closure_consistency.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <string>
#include <utility>

#include "core/error.h"

namespace partslam {
namespace {

// The travel along the two chain segments of a and b's cycle [m].
double chain_travel(const Submaps& maps, const LoopClosure& a, const LoopClosure& b) {
  return std::abs(maps[a.match].travel - maps[b.match].travel) +
         std::abs(maps[a.query].travel - maps[b.query].travel);
}

// The stored relative pose of submap v in submap u's frame.
Pose2 chain(const Submaps& maps, std::size_t u, std::size_t v) {
  return maps[u].T_world_map.inverse() * maps[v].T_world_map;
}

}  // namespace

void validate(const ClosureConsistencyConfig& c) {
  const std::pair<double, const char*> values[] = {{c.offset, "offset"},
                                                   {c.rate, "rate"},
                                                   {c.turn, "turn"},
                                                   {c.turn_rate, "turn_rate"},
                                                   {c.max_chain, "max_chain"}};
  for (const auto& [v, name] : values)
    if (!(v >= 0) || !std::isfinite(v))
      throw InputError(std::string("closure consistency config: ") + name + " must be finite and >= 0");
}

bool closures_agree(const Submaps& maps, const LoopClosure& a, const LoopClosure& b,
                    const ClosureConsistencyConfig& c) {
  const double travel = chain_travel(maps, a, b);
  const Pose2 E = a.T_match_query.inverse() * chain(maps, a.match, b.match) * b.T_match_query *
                  chain(maps, b.query, a.query);
  return E.translation().norm() <= c.offset + c.rate * travel &&
         std::abs(E.theta) <= c.turn + c.turn_rate * travel;
}

std::vector<bool> consistent_closures(const Submaps& maps, const std::vector<LoopClosure>& closures,
                                      const ClosureConsistencyConfig& c) {
  validate(c);
  const std::size_t n = closures.size();
  for (const LoopClosure& l : closures)
    if (l.query >= maps.size() || l.match >= maps.size())
      throw InputError("closure consistency: a closure names a submap out of range");
  // Disagreeing pairs, among closures whose queries lie within max_chain of travel (sorted by it).
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  const auto query_travel = [&](std::size_t k) { return maps[closures[k].query].travel; };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return query_travel(x) < query_travel(y); });
  std::vector<std::vector<std::size_t>> conflicts(n);
  for (std::size_t p = 0; p < n; ++p) {
    const LoopClosure& a = closures[order[p]];
    for (std::size_t q = p + 1; q < n && query_travel(order[q]) - query_travel(order[p]) <= c.max_chain;
         ++q) {
      const LoopClosure& b = closures[order[q]];
      if (chain_travel(maps, a, b) > c.max_chain || closures_agree(maps, a, b, c)) continue;
      conflicts[order[p]].push_back(order[q]);
      conflicts[order[q]].push_back(order[p]);
    }
  }
  // Greedy vertex cover of the disagreements: drop the closure with the most, the less confident first among
  // equals (then the later one), until none are left.
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
  std::vector<bool> kept(n, true);
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
  return kept;
}

}  // namespace partslam
