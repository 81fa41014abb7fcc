#include "core/evaluation/metrics.h"

#include <gtest/gtest.h>

namespace partslam {
namespace {

TEST(TiedRank, BestWorstAndTies) {
  EXPECT_DOUBLE_EQ(tied_rank({0.9, 0.1, 0.2}, 0), 1.0);
  EXPECT_DOUBLE_EQ(tied_rank({0.9, 0.1, 0.2}, 1), 3.0);
  // Four-way tie: ranks 1..4 shared, mean 2.5.
  EXPECT_DOUBLE_EQ(tied_rank({1, 1, 1, 1}, 2), 2.5);
  // One better, two tied with the relevant: ranks 2..4 shared -> 3.
  EXPECT_DOUBLE_EQ(tied_rank({5, 3, 3, 3, 1}, 1), 3.0);
}

TEST(SummarizeRanks, AnrAndRecall) {
  // N = 100: ranks 1, 50, 2.5 -> normalised 1 %, 50 %, 2.5 %.
  const RankSummary s = summarize_ranks({1, 50, 2.5}, {100, 100, 100});
  EXPECT_NEAR(s.anr_percent, (1 + 50 + 2.5) / 3.0, 1e-12);
  EXPECT_NEAR(s.recall_at_1, 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(s.recall_at_1pct, 1.0 / 3.0, 1e-12);
  EXPECT_EQ(s.tasks, 3u);
}

TEST(SummarizeRanks, RandomScoresGiveAboutFiftyPercent) {
  // All-tied scores are the worst-informed ranking: mean rank (N+1)/2.
  std::vector<double> ranks, scores(200, 0.0);
  std::vector<std::size_t> sizes;
  for (int i = 0; i < 10; ++i) ranks.push_back(tied_rank(scores, i)), sizes.push_back(200);
  EXPECT_NEAR(summarize_ranks(ranks, sizes).anr_percent, 50.25, 1e-9);
}

}  // namespace
}  // namespace partslam
