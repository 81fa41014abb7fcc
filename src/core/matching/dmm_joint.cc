// match_dmm_joint (dmm.h): one query against many maps, the maps searched best root bound first with the k-th
// best score so far as the bar, each by the depth-first branch-and-bound (dmm_branch_and_bound.cc).
#include <algorithm>
#include <cstddef>
#include <functional>
#include <iterator>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/matching/dmm.h"
#include "core/matching/dmm_internal.h"

namespace partslam {

std::vector<DmmResult> match_dmm_joint(const PreparedQuery& query, std::span<const PreparedMap* const> maps,
                                       int top_k) {
  using dmm_internal::BranchAndBound;
  using dmm_internal::Candidate;
  using dmm_internal::Range;
  using dmm_internal::check_compatible;
  using dmm_internal::make_result;
  using dmm_internal::search_ranges;
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

}  // namespace partslam
