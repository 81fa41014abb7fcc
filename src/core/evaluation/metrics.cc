#include "core/evaluation/metrics.h"

#include <algorithm>
#include <cassert>

#include "core/ranking/ranking.h"

namespace partslam {

double tied_rank(const std::vector<double>& scores, std::size_t relevant) {
  Ranking ranking;
  ranking.scores = scores;
  return tied_rank(ranking, relevant);
}

RankSummary summarize_ranks(const std::vector<double>& ranks, const std::vector<std::size_t>& db_sizes) {
  assert(ranks.size() == db_sizes.size());
  RankSummary r;
  r.tasks = ranks.size();
  if (ranks.empty()) return r;
  double sum = 0;
  std::size_t r1 = 0, r1pct = 0, r5pct = 0, r10pct = 0;
  for (std::size_t i = 0; i < ranks.size(); ++i) {
    sum += ranks[i] / static_cast<double>(db_sizes[i]);
    if (ranks[i] <= 1.0) ++r1;
    const double n_i = static_cast<double>(db_sizes[i]);
    if (ranks[i] <= std::max(1.0, 0.01 * n_i)) ++r1pct;
    if (ranks[i] <= std::max(1.0, 0.05 * n_i)) ++r5pct;
    if (ranks[i] <= std::max(1.0, 0.10 * n_i)) ++r10pct;
  }
  const double n = static_cast<double>(ranks.size());
  r.anr_percent = 100.0 * sum / n;
  r.recall_at_1 = static_cast<double>(r1) / n;
  r.recall_at_1pct = static_cast<double>(r1pct) / n;
  r.recall_at_5pct = static_cast<double>(r5pct) / n;
  r.recall_at_10pct = static_cast<double>(r10pct) / n;
  return r;
}

}  // namespace partslam
