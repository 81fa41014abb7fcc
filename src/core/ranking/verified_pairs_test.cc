#include "core/ranking/verified_pairs.h"

#include <gtest/gtest.h>

#include <numeric>
#include <string>

#include "core/error.h"
#include "core/ranking/ranking.h"
#include "core/testing/simulated_maps.h"

namespace partslam {
namespace {

TEST(VerifiedPairs, KeepsTheFirstAnswerOfAPairAndCountsHits) {
  VerifiedPairs pairs;
  EXPECT_FALSE(pairs.find(3, 7).has_value());
  VerifiedPair a;
  a.probability = 0.25, a.ms = 1.5;
  pairs.insert(3, 7, a);
  VerifiedPair b = a;
  b.probability = 0.75;
  pairs.insert(3, 7, b);  // the same pair again: the first stays
  const std::optional<VerifiedPair> kept = pairs.find(3, 7);
  ASSERT_TRUE(kept.has_value());
  EXPECT_EQ(kept->probability, 0.25);
  EXPECT_EQ(kept->ms, 1.5);
  EXPECT_FALSE(pairs.find(7, 3).has_value());  // ordered: query 7 against map 3 is another pair
  EXPECT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs.hits(), 1u);
  EXPECT_THROW(pairs.find(std::size_t{1} << 32, 0), InputError);
}

// What evaluation relies on: a ranking that reuses kept answers is the ranking that computes them, for `dmm` and
// for a rerank's dMM stage, and it charges each reused pair the time it took when computed.
TEST(VerifiedPairs, ARankingThatReusesAnswersIsTheRankingThatComputesThem) {
  const Submaps& maps = testing::simulated_maps();
  ASSERT_GT(maps.size(), 40u);
  const std::vector<MapView> views = testing::point_views(maps);
  const std::vector<std::size_t> candidates = {3, 10, 0, 25, 40, 12};
  VerifiedPairs pairs;
  for (const char* spec : {"dmm", "rerank:3:succinct"}) {
    const std::unique_ptr<Ranker> ranker = make_ranker(parse_method_spec(spec), {});
    ranker->prepare(views, 2);
    const Ranking computed = ranker->rank(views[0], candidates, {1, 0});
    RankOptions reuse{1, 0, &pairs, 0};
    const Ranking first = ranker->rank(views[0], candidates, reuse);   // dmm: computes and keeps every pair
    const std::size_t hits = pairs.hits();
    const Ranking second = ranker->rank(views[0], candidates, reuse);  // every pair found
    EXPECT_EQ(pairs.hits() - hits, std::string(spec) == "dmm" ? candidates.size() : 3u) << spec;
    for (const Ranking* r : {&first, &second}) {
      EXPECT_EQ(r->scores, computed.scores) << spec;
      EXPECT_EQ(r->probability, computed.probability) << spec;
      EXPECT_EQ(r->runner_up, computed.runner_up) << spec;
      EXPECT_EQ(r->tiers, computed.tiers) << spec;
      ASSERT_EQ(r->direct.size(), computed.direct.size());
      for (std::size_t j = 0; j < r->direct.size(); ++j) {
        ASSERT_EQ(r->direct[j].has_value(), computed.direct[j].has_value()) << spec << " " << j;
        if (!r->direct[j]) continue;
        EXPECT_EQ(r->direct[j]->inliers, computed.direct[j]->inliers);
        EXPECT_EQ(r->direct[j]->T_map_query.translation(), computed.direct[j]->T_map_query.translation());
        EXPECT_EQ(r->direct[j]->T_map_query.theta, computed.direct[j]->T_map_query.theta);
      }
    }
    // Reused answers are charged the time they took when computed, not the lookup's (a rerank adds its first
    // stage's own time).
    if (std::string(spec) == "dmm") {
      EXPECT_EQ(second.match_ms, first.match_ms);
    }
    EXPECT_GT(second.match_ms, 0.0) << spec;
  }
  // Query 1 against the same maps is another set of pairs.
  const std::unique_ptr<Ranker> dmm = make_ranker(parse_method_spec("dmm"), {});
  dmm->prepare(views, 2);
  const std::size_t before = pairs.size();
  dmm->rank(views[1], candidates, {1, 0, &pairs, 1});
  EXPECT_EQ(pairs.size(), before + candidates.size());
}

}  // namespace
}  // namespace partslam
