#include "core/ranking/ranking.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"

namespace partslam {
namespace {

// Candidate i's key: no tiers put every candidate in tier 0, no shortlist scores leave the stage score 0.
RankKey rank_key(const Ranking& r, std::size_t i) {
  return {r.tiers.empty() ? 0 : r.tiers.at(i), r.scores.at(i),
          r.shortlist_scores.empty() ? 0.0 : r.shortlist_scores.at(i)};
}

// -1, 0 or 1 as candidate a ranks below, level with or above candidate b.
int compare(const Ranking& r, std::size_t a, std::size_t b) { return compare_rank(rank_key(r, a), rank_key(r, b)); }

}  // namespace

int compare_rank(const RankKey& a, const RankKey& b) {
  const auto cmp = [](auto x, auto y) { return x > y ? 1 : x < y ? -1 : 0; };
  if (const int c = cmp(a.tier, b.tier); c != 0) return c;
  if (const int c = cmp(a.score, b.score); c != 0) return c;
  return cmp(a.stage_score, b.stage_score);
}

void validate(const RankingConfig& config) {
  validate(config.dmm);
  validate(config.ransac);
  validate(config.verify);
  validate(config.parts);
  if (!(config.bits_per_point >= 0) || !std::isfinite(config.bits_per_point))
    throw InputError("ranking: bits_per_point must be a finite number >= 0");
}

std::unique_ptr<Ranker> make_ranker(const MethodSpec& method, const RankingConfig& config) {
  const MethodEntry* entry = find_method(method.name);
  if (entry == nullptr) throw InputError("ranking: unknown method '" + method.name + "'");
  validate(config);
  return entry->make(method, config);
}

std::vector<std::size_t> ranking_order(const std::vector<double>& scores) {
  Ranking r;
  r.scores = scores;
  return ranking_order(r);
}

bool ranks_above(const Ranking& ranking, std::size_t a, std::size_t b) { return compare(ranking, a, b) > 0; }

std::vector<std::size_t> ranking_order(const Ranking& ranking) {
  std::vector<std::size_t> order(ranking.scores.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return compare(ranking, a, b) > 0; });
  return order;
}

double tied_rank(const Ranking& ranking, std::size_t j) {
  std::size_t better = 0, tied = 0;
  for (std::size_t i = 0; i < ranking.scores.size(); ++i) {
    if (i == j) continue;
    const int c = compare(ranking, i, j);
    if (c > 0) ++better;
    else if (c == 0) ++tied;
  }
  // Ranks better+1 .. better+1+tied are shared by the tied group; j gets their mean.
  return static_cast<double>(better) + 1.0 + static_cast<double>(tied) / 2.0;
}

}  // namespace partslam
