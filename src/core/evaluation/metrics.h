// Ranking metrics (docs/DESIGN.md, "Metrics"; paper, "Performance Metrics", ref. [17]). The normalised rank of the
// relevant map is rank / N with rank 1 = best and tied scores sharing their mean rank; ANR is its mean over
// tasks in percent (a random ranking scores about 50 %).
#pragma once

#include <cstddef>
#include <vector>

namespace partslam {

/// Rank (1 = best, ties share the mean rank) of scores[relevant] among scores; higher score = better (the plain
/// scores' case of core/ranking/ranking.h's tied_rank).
double tied_rank(const std::vector<double>& scores, std::size_t relevant);

struct RankSummary {
  double anr_percent = 0;       ///< mean normalised rank [%]
  double recall_at_1 = 0;       ///< share of tasks with rank 1 (no tie) [0..1]
  double recall_at_1pct = 0;    ///< share of tasks whose rank <= max(1, 1 % of N) [0..1]
  double recall_at_5pct = 0;    ///< share of tasks whose rank <= max(1, 5 % of N) [0..1]
  double recall_at_10pct = 0;   ///< share of tasks whose rank <= max(1, 10 % of N) [0..1] (what reranking needs)
  std::size_t tasks = 0;
};

/// ranks[i] is the tied rank of task i, db_sizes[i] its N.
RankSummary summarize_ranks(const std::vector<double>& ranks, const std::vector<std::size_t>& db_sizes);

}  // namespace partslam
